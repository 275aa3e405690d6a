// libFuzzer target: .npy ray files (src/relief/io/npy.cpp's header reader and the (N,6)/(N,7)
// float32/float64 ray reader in src/relief/io/ray_io.cpp). Parsed rays have finite origins within
// kMaxRayOrigin, unit directions and a tMax >= 0, and written back they read back the same.
// Seeds: fuzz/corpus/npy/.
#include <relief/io/ray_io.h>

#include <span>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace relief;
    // A small --max-rays, so that the fuzzer spends its time in the header and row checks.
    auto rays = decodeNpyRays(std::span<const unsigned char>(data, size), "fuzz.npy", 1 << 16);
    if (!rays) {
        RELIEF_FUZZ_EXPECT(!rays.error().message.empty());
        return 0;
    }
    for (const Ray& r : *rays) {
        for (int a = 0; a < 3; ++a) {
            RELIEF_FUZZ_EXPECT(std::isfinite(r.origin[a]));
            RELIEF_FUZZ_EXPECT(std::abs(double(r.origin[a])) <= kMaxRayOrigin);
        }
        RELIEF_FUZZ_EXPECT(std::abs(glm::length(r.direction) - 1.0f) < 1e-4f);
        RELIEF_FUZZ_EXPECT(r.tMax >= 0.0f);
    }
    const std::string again = npyRays(*rays);
    auto back =
        decodeNpyRays(std::span(reinterpret_cast<const unsigned char*>(again.data()), again.size()),
                      "again.npy", 1 << 16);
    RELIEF_FUZZ_EXPECT(back && back->size() == rays->size());
    for (size_t k = 0; k < rays->size(); ++k) {
        RELIEF_FUZZ_EXPECT((*back)[k].origin == (*rays)[k].origin);
        RELIEF_FUZZ_EXPECT((*back)[k].direction == (*rays)[k].direction);
        RELIEF_FUZZ_EXPECT((*back)[k].tMax == (*rays)[k].tMax);
    }
    return 0;
}
