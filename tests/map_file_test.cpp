#include <relief/core/parallel.h>
#include <relief/io/heightfield_io.h>
#include <relief/io/map_file.h>
#include <relief/techniques/registry.h>

#include "support/map_flip.h"
#include "support/ray_sets.h"

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace relief {
namespace {

namespace fs = std::filesystem;

MapFile sampleMaps() {
    MapFile file;
    file.source = {0x1234abcdull, 5, 3, "clamp", 2.5f};
    TechniqueMaps t{"quadtree", {{"levels", "3"}}, {}};
    t.arrays.push_back({"level0", 5, 3, 1, std::vector<float>(15)});
    t.arrays.push_back({"level1", 3, 2, 2, std::vector<float>(12)});
    for (size_t k = 0; k < 15; ++k) t.arrays[0].data[k] = float(k) * 0.5f;
    for (size_t k = 0; k < 12; ++k) t.arrays[1].data[k] = -float(k);
    file.techniques.push_back(t);
    return file;
}

fs::path tempPath(const char* name) {
    return fs::temp_directory_path() / (std::string("relief_map_") + std::to_string(::getpid()) + name);
}

TEST(MapFile, RoundTrip) {
    const fs::path path = tempPath("rt.exr");
    const MapFile written = sampleMaps();
    const Status status = writeMapFile(path.string(), written);
    ASSERT_TRUE(status.ok()) << status.error().message;
    auto read = readMapFile(path.string());
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->source.heightfieldHash, written.source.heightfieldHash);
    EXPECT_EQ(read->source.edge, "clamp");
    const TechniqueMaps* t = read->find("quadtree");
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->parameters.at("levels"), "3");
    ASSERT_NE(t->find("level1"), nullptr);
    EXPECT_EQ(t->find("level1")->channels, 2);
    EXPECT_EQ(t->find("level1")->data, written.techniques[0].arrays[1].data);
    EXPECT_EQ(t->find("level0")->data, written.techniques[0].arrays[0].data);
    fs::remove(path);
}

// The in-memory reader (what fuzz/fuzz_map_file.cpp uses) sees the same file and the same damage.
TEST(MapFile, FromMemoryMatchesFromFile) {
    const fs::path path = tempPath("mem.exr");
    ASSERT_TRUE(writeMapFile(path.string(), sampleMaps()).ok());
    std::ifstream in(path, std::ios::binary);
    const std::vector<unsigned char> bytes(std::istreambuf_iterator<char>(in), {});
    fs::remove(path);
    auto read = readMapFile(bytes, "mem.exr");
    ASSERT_TRUE(read.ok()) << read.error().message;
    const TechniqueMaps* t = read->find("quadtree");
    ASSERT_NE(t, nullptr);
    ASSERT_EQ(t->arrays.size(), 2u);
    EXPECT_EQ(t->arrays[1].channels, 2);
    EXPECT_EQ(t->arrays[1].data, sampleMaps().techniques[0].arrays[1].data);
    for (size_t keep : {size_t(0), size_t(4), bytes.size() / 2, bytes.size() - 1}) {
        auto cut = readMapFile(std::span(bytes.data(), keep), "cut.exr");
        ASSERT_FALSE(cut.ok()) << keep;
        EXPECT_EQ(cut.error().message.rfind("cut.exr: cannot read map file: ", 0), 0u)
            << cut.error().message;
    }
}

// Found by fuzz_map_file: an attribute whose size field claims 2 GB made OpenEXR allocate that
// much for a file of a few KB. Refused before OpenEXR reads the header, from a file or memory.
TEST(MapFile, AttributeClaimingMoreThanTheFileIsRefused) {
    const fs::path path = tempPath("claims.exr");
    ASSERT_TRUE(writeMapFile(path.string(), sampleMaps()).ok());
    std::vector<unsigned char> bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const unsigned char attribute[] = {'n', 'o', 't', 'e', 0, 'o', 'p', 'a', 'q', 'u', 'e', 0,
                                       0x00, 0x00, 0x00, 0x78, 1, 2, 3, 4};  // 0x78000000 bytes
    bytes.insert(bytes.begin() + 8, std::begin(attribute), std::end(attribute));
    {
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    for (auto read : {readMapFile(path.string()), readMapFile(bytes, path.string())}) {
        ASSERT_FALSE(read.ok());
        EXPECT_EQ(read.error().kind, ErrorKind::InvalidInput);
        EXPECT_NE(read.error().message.find("cannot read map file: attribute 'note' (opaque) "
                                            "claims more bytes than the file has left"),
                  std::string::npos)
            << read.error().message;
    }
    fs::remove(path);
}

TEST(MapFile, StaleOrMismatchedSourceIsRefused) {
    const MapSource stored{1, 5, 3, "clamp", 2.5f};
    EXPECT_TRUE(checkMapSource("m.exr", stored, stored).ok());
    MapSource other = stored;
    other.heightfieldHash = 2;
    auto s = checkMapSource("m.exr", stored, other);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("stale maps"), std::string::npos);
    other = stored;
    other.edge = "repeat";
    EXPECT_NE(checkMapSource("m.exr", stored, other).error().message.find("--edge clamp"), std::string::npos);
    other = stored;
    other.width = 6;
    EXPECT_NE(checkMapSource("m.exr", stored, other).error().message.find("5x3"), std::string::npos);
    other = stored;
    other.depth = 3.0f;
    EXPECT_NE(checkMapSource("m.exr", stored, other).error().message.find("depth"), std::string::npos);
}

TEST(MapFile, CorruptAndTruncatedFilesAreErrors) {
    const fs::path path = tempPath("bad.exr");
    ASSERT_TRUE(writeMapFile(path.string(), sampleMaps()).ok());
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (size_t cut : {size_t(0), size_t(10), bytes.size() / 2, bytes.size() - 4}) {
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, cut);
        auto read = readMapFile(path.string());
        EXPECT_FALSE(read.ok()) << "cut at " << cut;
    }
    std::ofstream(path, std::ios::binary | std::ios::trunc) << "not an exr";
    EXPECT_FALSE(readMapFile(path.string()).ok());
    EXPECT_FALSE(readMapFile((path.string() + ".missing")).ok());
    fs::remove(path);
}

// OpenEXR (de)compresses a file's blocks on its worker pool, sized to the thread limit
// (exrThreads): files of many blocks are the same bytes and read back as the same floats on one
// thread or several, and damage in a block a worker decodes is an error, not a crash.
TEST(MapFile, SeveralThreadsWriteAndReadTheSameMaps) {
    MapFile maps = sampleMaps();
    TechniqueMaps t{"safety-cc", {}, {}};
    t.arrays.push_back({"x+", 257, 203, 3, std::vector<float>(size_t(257) * 203 * 3)});
    t.arrays.push_back({"y+", 257, 203, 1, std::vector<float>(size_t(257) * 203)});
    uint32_t state = 12345u;
    for (MapArray& a : t.arrays)
        for (float& v : a.data) {
            state = state * 1664525u + 1013904223u;  // varied floats: real work for zip
            v = float(state >> 8) * 0x1p-12f - 2048.0f;
        }
    maps.techniques.push_back(t);
    std::string bytes[2];
    const int threads[2] = {1, 4};
    for (int k = 0; k < 2; ++k) {
        const ThreadLimit limit(threads[k]);
        const fs::path path = tempPath(("threads" + std::to_string(threads[k]) + ".exr").c_str());
        ASSERT_TRUE(writeMapFile(path.string(), maps).ok());
        std::ifstream in(path, std::ios::binary);
        bytes[k].assign(std::istreambuf_iterator<char>(in), {});
        for (int readThreads : {1, 4}) {
            const ThreadLimit readLimit(readThreads);
            auto read = readMapFile(path.string());
            ASSERT_TRUE(read.ok()) << read.error().message;
            const TechniqueMaps* back = read->find("safety-cc");
            ASSERT_NE(back, nullptr);
            EXPECT_EQ(back->find("x+")->data, t.arrays[0].data) << readThreads << " threads";
            EXPECT_EQ(back->find("y+")->data, t.arrays[1].data) << readThreads << " threads";
        }
        fs::remove(path);
    }
    EXPECT_EQ(bytes[0], bytes[1]);
    // A byte in the middle of the data: a block one of the workers inflates.
    std::string damaged = bytes[1];
    damaged[damaged.size() / 2] = char(damaged[damaged.size() / 2] ^ 0x5a);
    const ThreadLimit limit(4);
    const auto read = readMapFile(
        std::span(reinterpret_cast<const unsigned char*>(damaged.data()), damaged.size()),
        "damaged.exr");
    EXPECT_FALSE(read.ok());
}

TEST(MapFile, FailedWriteLeavesPreviousFileUntouched) {
    const fs::path path = tempPath("keep.exr");
    ASSERT_TRUE(writeMapFile(path.string(), sampleMaps()).ok());
    const auto size = fs::file_size(path);
    MapFile broken = sampleMaps();
    broken.techniques[0].arrays[0].data.resize(3);  // malformed: refused before writing
    EXPECT_FALSE(writeMapFile(path.string(), broken).ok());
    EXPECT_EQ(fs::file_size(path), size);
    EXPECT_TRUE(readMapFile(path.string()).ok());
    fs::remove(path);
}

// ---- Integrity (issue 22, class 3): checksum, validated attributes, spot-checked invariants ----

using Bytes = std::vector<unsigned char>;

Bytes bytesOf(const MapFile& maps, const char* name) {
    const fs::path path = tempPath(name);
    const Status written = writeMapFile(path.string(), maps);
    EXPECT_TRUE(written.ok()) << written.error().message;
    std::ifstream in(path, std::ios::binary);
    Bytes bytes(std::istreambuf_iterator<char>(in), {});
    fs::remove(path);
    return bytes;
}

// Replaces the first occurrence of `from` (an attribute value as stored) by `to`, same length.
Bytes edited(Bytes bytes, const std::string& from, const std::string& to) {
    auto at = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
    EXPECT_NE(at, bytes.end()) << from;
    if (at != bytes.end()) std::copy(to.begin(), to.end(), at);
    return bytes;
}

TEST(MapIntegrity, FlippedDataByteFailsTheChecksum) {
    const Bytes bytes = bytesOf(sampleMaps(), "flip.exr");
    ASSERT_TRUE(readMapFile(bytes, "flip.exr").ok());
    // The last bytes are level1's floats (uncompressed scanlines): a flip changes a value.
    Bytes flipped = bytes;
    flipped[flipped.size() - 3] ^= 0x10;
    auto read = readMapFile(flipped, "flip.exr");
    ASSERT_FALSE(read.ok());
    EXPECT_EQ(read.error().kind, ErrorKind::InvalidInput);
    EXPECT_EQ(read.error().message.rfind(
                  "flip.exr: map file damaged: part 'quadtree/level1' has checksum crc32:", 0),
              0u)
        << read.error().message;
}

// The checksum is a function of the maps: the same maps give the same bytes, other data another.
TEST(MapIntegrity, ChecksumIsDeterministicAndCoversTheData) {
    const Bytes first = bytesOf(sampleMaps(), "det1.exr"),
                second = bytesOf(sampleMaps(), "det2.exr");
    EXPECT_EQ(first, second);
    MapFile other = sampleMaps();
    other.techniques[0].arrays[1].data[5] += 1.0f;
    const Bytes changed = bytesOf(other, "det3.exr");
    const std::string marker = "crc32:";
    auto checksums = [&](const Bytes& b) {
        std::vector<std::string> found;
        for (auto at = std::search(b.begin(), b.end(), marker.begin(), marker.end()); at != b.end();
             at = std::search(at + 1, b.end(), marker.begin(), marker.end()))
            found.emplace_back(at, at + 14);
        return found;
    };
    ASSERT_EQ(checksums(first).size(), 2u);                 // one per part
    EXPECT_EQ(checksums(changed)[0], checksums(first)[0]);  // level0 unchanged
    EXPECT_NE(checksums(changed)[1], checksums(first)[1]);
    EXPECT_TRUE(readMapFile(changed, "det3.exr").ok());
}

// Each relief attribute is covered by the checksum and validated on its own (a value of the wrong
// form is named before the checksum is compared).
TEST(MapIntegrity, EveryAttributeIsValidated) {
    const Bytes bytes = bytesOf(sampleMaps(), "attr.exr");
    const struct {
        const char* from;
        const char* to;
        const char* fragment;
    } cases[] = {
        {"2.5", "nan", "relief.source.depth 'nan' is not a depth from 0 to 1e6"},
        {"2.5", "inf", "relief.source.depth 'inf'"},
        {"2.5", "-25", "relief.source.depth '-25'"},
        {"clamp", "cramp", "relief.source.edge 'cramp' is not clamp or repeat"},
        {"5x3", "5y3", "relief.source.size '5y3'"},
        {"5x3", "0x3", "relief.source.size '0x3'"},
        {"000000001234abcd", "000000001234abcg", "relief.source.hash '000000001234abcg'"},
        {"levels=3", "levels=x", "malformed names or parameters"},
        {"levels=3", "levels=4", "has checksum"},
        {"level0", "level9", "malformed names"},  // the part name, first
        {"crc32:", "crc31:", "has checksum crc31:"},
        {"relief.checksum", "relief.checksuX", "has no checksum"},
    };
    for (const auto& c : cases) {
        auto read = readMapFile(edited(bytes, c.from, c.to), "attr.exr");
        ASSERT_FALSE(read.ok()) << c.from << " -> " << c.to;
        EXPECT_EQ(read.error().kind, ErrorKind::InvalidInput) << c.to;
        EXPECT_NE(read.error().message.find(c.fragment), std::string::npos) << read.error().message;
        EXPECT_EQ(read.error().message.rfind("attr.exr: ", 0), 0u) << read.error().message;
    }
}

// A NaN depth used to pass the stale-map check (every comparison with NaN is false).
TEST(MapIntegrity, NanDepthNeverMatches) {
    const MapSource current{1, 5, 3, "clamp", 2.5f};
    MapSource stored = current;
    stored.depth = std::nanf("");
    EXPECT_FALSE(checkMapSource("m.exr", stored, current).ok());
    EXPECT_FALSE(checkMapSource("m.exr", current, stored).ok());
}

// Version 1 maps (no checksum) are refused with a message saying to bake them again.
TEST(MapIntegrity, VersionOneMapsAskToBeBakedAgain) {
    const fs::path path = tempPath("v1.exr");
    {
        Imf::Header h(2, 2);
        h.channels().insert("c0", Imf::Channel(Imf::FLOAT));
        h.insert("relief.version", Imf::IntAttribute(1));
        h.insert("relief.technique", Imf::StringAttribute("quadtree"));
        h.insert("relief.parameters", Imf::StringAttribute(""));
        Imf::OutputFile out(path.c_str(), h);
    }
    auto read = readMapFile(path.string());
    fs::remove(path);
    ASSERT_FALSE(read.ok());
    EXPECT_EQ(read.error().kind, ErrorKind::Unsupported);
    EXPECT_NE(read.error().message.find("map format version 1 has no checksum"), std::string::npos)
        << read.error().message;
    EXPECT_NE(read.error().message.find("bake the maps again"), std::string::npos);
}

TEST(MapIntegrity, TwinPartsAreRefusedBeforeWriting) {
    MapFile twice = sampleMaps();
    twice.techniques.push_back(twice.techniques[0]);
    const Status s = writeMapFile(tempPath("twice.exr").string(), twice);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().kind, ErrorKind::BadArgument);
    EXPECT_NE(s.error().message.find("quadtree/level0 given twice"), std::string::npos)
        << s.error().message;
    EXPECT_FALSE(fs::exists(tempPath("twice.exr")));
}

std::shared_ptr<const Surface> smallSurface(EdgeMode edge = EdgeMode::Clamp) {
    auto hf = loadHeightfield("gen:fbm:12x10:3");
    EXPECT_TRUE(hf.ok());
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(*hf)),
                                           4.0f, edge);
}

MapFile bakedFor(std::shared_ptr<const Surface> surface, const TechniqueInfo& info) {
    auto input = techniqueInput(info, surface, {});
    EXPECT_TRUE(input.ok());
    auto maps = info.buildMaps(*input);
    EXPECT_TRUE(maps.ok()) << info.name;
    MapFile file;
    file.source = mapSourceOf(*surface);
    file.techniques.push_back(std::move(*maps));
    return file;
}

// Values edited by hand and written with a valid checksum: the spot checks refuse them, naming
// the file and what failed.
TEST(MapIntegrity, EditedValuesAreRefusedBySpotChecks) {
    const auto surface = smallSurface();
    const struct {
        const char* technique;
        const char* array;    // null: every array
        float scale, offset;  // value = value * scale + offset, on every texel
        int channel;          // -1: every channel
        const char* fragment;
    } cases[] = {
        {"cone", "cones", 2.0f, 0.0f, 1, "has ratio"},
        {"cone", "cones", 1.0f, -1.0f, 1, "has ratio -"},
        {"cone", "cones", 0.0f, 0.0f, 0, "has apex 0"},
        {"cone", "cones", 0.5f, 0.0f, 0, "outside [sample"},
        {"relaxed-cone", "cones", 0.0f, -1.0f, 0, "has apex -1"},
        {"quadtree", "level1", 0.5f, 0.0f, -1, "'level1' node"},
        {"maxmip", nullptr, 0.0f, 0.0f, -1, "but the heightfield gives"},
        {"quadtree-oriented", "level2", 1.0f, 1.0f, -1, "but its children give"},
        {"quadtree-oriented", "oriented1", 1.0f, -0.5f, -1, "'oriented1' node"},
        {"qdm", "qdm", 1.0f, -1.0f, 0, "invalid entry"},
        {"safety-sd", "sd", 0.5f, 0.25f, -1, "bad safety distance"},
    };
    for (const auto& c : cases) {
        const TechniqueInfo* info = findTechnique(c.technique);
        ASSERT_NE(info, nullptr) << c.technique;
        MapFile maps = bakedFor(surface, *info);
        ASSERT_TRUE(!c.array || maps.techniques[0].find(c.array)) << c.technique << " " << c.array;
        for (MapArray& a : maps.techniques[0].arrays)
            if (!c.array || a.name == c.array)
                for (size_t k = 0; k < a.data.size(); ++k)
                    if (c.channel < 0 || int(k % size_t(a.channels)) == c.channel)
                        a.data[k] = a.data[k] * c.scale + c.offset;
        auto read = readMapFile(bytesOf(maps, "edited.exr"), "edited.exr");  // a valid checksum
        ASSERT_TRUE(read.ok()) << read.error().message;
        auto hits = testing::hitsWithMaps(*info, surface, *read, {});
        ASSERT_FALSE(hits.ok()) << c.technique << " accepted " << c.array << " edited";
        EXPECT_EQ(hits.error().kind, ErrorKind::InvalidInput);
        EXPECT_EQ(hits.error().message.rfind("edited.exr: ", 0), 0u) << hits.error().message;
        EXPECT_NE(hits.error().message.find(c.fragment), std::string::npos) << hits.error().message;
    }
}

// The mutator of issue 22: every byte of a valid map file of each row flipped in turn (one bit,
// a different one per byte; in repeat mode every seventh byte, to keep the test short). Each flip
// is refused, or the file reads back and every hit equals the unflipped maps' hits.
TEST(MapIntegrity, EveryFlippedByteIsRefusedOrChangesNoHit) {
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const auto surface = smallSurface(edge);
        const std::vector<Ray> rays = testing::RaySets(*surface, 7).fromOutside(200);
        for (const TechniqueInfo& info : techniques()) {
            if (!info.buildMaps) continue;
            const MapFile maps = bakedFor(surface, info);
            const Bytes bytes = bytesOf(maps, "mutate.exr");
            auto reference = testing::hitsWithMaps(info, surface, maps, rays);
            ASSERT_TRUE(reference.ok()) << info.name << ": " << reference.error().message;
            size_t refused = 0, accepted = 0;
            for (size_t k = 0; k < bytes.size(); k += edge == EdgeMode::Clamp ? 1 : 7) {
                Bytes flipped = bytes;
                flipped[k] ^= uint8_t(1u << (k % 8));
                auto read = readMapFile(flipped, "mutate.exr");
                auto hits = read ? testing::hitsWithMaps(info, surface, *read, rays)
                                 : Result<std::vector<Hit>>(read.error());
                if (!hits) {
                    ++refused;
                    continue;
                }
                ++accepted;
                ASSERT_TRUE(testing::sameHits(*hits, *reference))
                    << info.name << ": byte " << k << " of " << bytes.size()
                    << " flipped changes hits";
            }
            EXPECT_GT(refused, 2 * accepted) << info.name;
            RecordProperty(
                std::string(info.name) + (edge == EdgeMode::Clamp ? "_clamp" : "_repeat"),
                fmt::format("{} refused, {} accepted with the same hits", refused, accepted));
        }
    }
}

}  // namespace
}  // namespace relief
