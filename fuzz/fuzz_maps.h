#pragma once
// What the map-file fuzz targets share (fuzz_map_file, fuzz_ktx2, fuzz_png_maps): the bytes read
// by readMapFile, which picks the container from them (EXR, PNG, KTX2); a file that reads is
// checked against its own source the way the CLI checks it, and its attributes must be valid.
#include "fuzz_common.h"

#include <relief/io/map_file.h>

namespace relief::fuzz {

inline void checkMapBytes(std::span<const unsigned char> bytes, const char* name) {
    auto maps = readMapFile(bytes, name);
    if (!maps) return;
    RELIEF_FUZZ_EXPECT(checkMapSource(name, maps->source, maps->source).ok());
    const MapSource& s = maps->source;
    RELIEF_FUZZ_EXPECT(s.width >= 1 && s.height >= 1 && s.width <= kMaxDimension &&
                       s.height <= kMaxDimension);
    RELIEF_FUZZ_EXPECT(std::isfinite(s.depth) && s.depth >= 0.0f && s.depth <= 1e6f);
    RELIEF_FUZZ_EXPECT(s.edge == "clamp" || s.edge == "repeat");
    for (const TechniqueMaps& t : maps->techniques) {
        RELIEF_FUZZ_EXPECT(maps->find(t.technique) != nullptr);
        for (const MapArray& a : t.arrays) {
            RELIEF_FUZZ_EXPECT(a.width >= 1 && a.height >= 1 && a.channels >= 1);
            RELIEF_FUZZ_EXPECT(a.data.size() ==
                               size_t(a.width) * size_t(a.height) * size_t(a.channels));
        }
    }
}

}  // namespace relief::fuzz
