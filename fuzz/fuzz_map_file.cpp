// libFuzzer target: baked map files (src/relief/io/map_file.cpp, multi-part OpenEXR). A file that
// reads is checked against its own source the way the CLI checks it. Seeds: fuzz/corpus/map_file/.
#include "fuzz_common.h"

#include <relief/io/map_file.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace relief;
    auto maps = readMapFile(std::span<const unsigned char>(data, size), "fuzz.maps.exr");
    if (!maps) return 0;
    RELIEF_FUZZ_EXPECT(checkMapSource("fuzz.maps.exr", maps->source, maps->source).ok());
    for (const TechniqueMaps& t : maps->techniques) {
        RELIEF_FUZZ_EXPECT(maps->find(t.technique) != nullptr);
        for (const MapArray& a : t.arrays) {
            RELIEF_FUZZ_EXPECT(a.width >= 1 && a.height >= 1 && a.channels >= 1);
            RELIEF_FUZZ_EXPECT(a.data.size() ==
                               size_t(a.width) * size_t(a.height) * size_t(a.channels));
        }
    }
    return 0;
}
