// libFuzzer target: ray files for `relief trace` (src/relief/io/ray_io.cpp). Parsed rays have
// finite origins within kMaxRayOrigin, unit directions and tMax >= 0; the hit file of as many
// misses has one line per ray.
// Seeds: fuzz/corpus/ray_file/.
#include "fuzz_common.h"

#include <relief/io/ray_io.h>

#include <algorithm>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace relief;
    auto rays = parseRays(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.csv");
    if (!rays) return 0;
    for (const Ray& r : *rays) {
        RELIEF_FUZZ_EXPECT(std::isfinite(r.origin.x) && std::isfinite(r.origin.y) &&
                           std::isfinite(r.origin.z));
        RELIEF_FUZZ_EXPECT(std::abs(glm::length(r.direction) - 1.0f) < 1e-4f);
        for (int a = 0; a < 3; ++a) RELIEF_FUZZ_EXPECT(std::abs(double(r.origin[a])) <= kMaxRayOrigin);
        RELIEF_FUZZ_EXPECT(r.tMax >= 0.0f);
    }
    const std::string hits = formatHits(std::vector<Hit>(rays->size()));
    RELIEF_FUZZ_EXPECT(size_t(std::count(hits.begin(), hits.end(), '\n')) == rays->size() + 1);
    return 0;
}
