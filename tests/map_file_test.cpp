#include <relief/io/map_file.h>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace relief
