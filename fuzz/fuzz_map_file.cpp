// libFuzzer target: baked map files (src/relief/io/map_file.cpp, multi-part OpenEXR). A file that
// reads is checked against its own source the way the CLI checks it, and its attributes must be
// valid. Inputs starting with "FLIP" are the map-file mutator of issue 22 instead: one bit of a
// valid map file of one row (baked here on gen:fbm:8x8) is flipped, and the flip must be refused
// or leave every hit identical. Seeds: fuzz/corpus/map_file/.
#include "fuzz_common.h"
#include "fuzz_maps.h"
#include "../tests/support/map_flip.h"

#include <relief/io/map_file.h>
#include <relief/techniques/registry.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace {

using namespace relief;

struct Baked {
    const TechniqueInfo* info;
    std::vector<unsigned char> bytes;
    std::vector<Hit> hits;
};

std::shared_ptr<const Surface> fuzzSurface() {
    static const auto surface = [] {
        auto hf = loadHeightfield("gen:fbm:8x8:5");
        RELIEF_FUZZ_EXPECT(hf.ok());
        return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(*hf)),
                                               2.0f, EdgeMode::Clamp);
    }();
    return surface;
}

// A fan of rays from above the box through its whole footprint.
const std::vector<Ray>& fuzzRays() {
    static const std::vector<Ray> rays = [] {
        std::vector<Ray> r;
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i)
                r.push_back({vec3(float(i) + 0.3f, float(j) + 0.6f, 4.0f),
                             normalize(vec3(0.4f, -0.3f, -1.0f))});
        return r;
    }();
    return rays;
}

// Hits with these maps, or an empty vector when the maps (or the tracer) are refused.
std::vector<Hit> hitsWith(const TechniqueInfo& info, const MapFile& maps) {
    auto hits = testing::hitsWithMaps(info, fuzzSurface(), maps, fuzzRays());
    return hits ? std::move(*hits) : std::vector<Hit>();
}

const std::vector<Baked>& bakedRows() {
    static const std::vector<Baked> rows = [] {
        std::vector<Baked> out;
        const auto path = std::filesystem::temp_directory_path() /
                          ("relief_fuzz_maps_" + std::to_string(::getpid()) + ".exr");
        for (const TechniqueInfo& info : techniques()) {
            if (!info.buildMaps) continue;
            auto input = techniqueInput(info, fuzzSurface(), {});
            RELIEF_FUZZ_EXPECT(input.ok());
            auto maps = info.buildMaps(*input);
            RELIEF_FUZZ_EXPECT(maps.ok());
            MapFile file;
            file.source = mapSourceOf(*fuzzSurface());
            file.techniques.push_back(std::move(*maps));
            RELIEF_FUZZ_EXPECT(writeMapFile(path.string(), file).ok());
            std::ifstream in(path, std::ios::binary);
            Baked b{&info, std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {}),
                    hitsWith(info, file)};
            RELIEF_FUZZ_EXPECT(!b.hits.empty());
            out.push_back(std::move(b));
        }
        std::filesystem::remove(path);
        return out;
    }();
    return rows;
}

// "FLIP", row, byte position (4 bytes, little endian, modulo the file size), bit.
void flipOne(const uint8_t* data, size_t size) {
    if (size < 10) return;
    const auto& rows = bakedRows();
    const Baked& row = rows[data[4] % rows.size()];
    uint32_t position = 0;
    std::memcpy(&position, data + 5, 4);
    std::vector<unsigned char> bytes = row.bytes;
    bytes[position % bytes.size()] ^= uint8_t(1u << (data[9] % 8));
    auto maps = readMapFile(bytes, "fuzz.maps.exr");
    if (!maps) return;
    const std::vector<Hit> hits = hitsWith(*row.info, *maps);
    RELIEF_FUZZ_EXPECT(hits.empty() || testing::sameHits(hits, row.hits));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size >= 4 && std::memcmp(data, "FLIP", 4) == 0) {
        flipOne(data, size);
        return 0;
    }
    fuzz::checkMapBytes({data, size}, "fuzz.maps.exr");
    return 0;
}
