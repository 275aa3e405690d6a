#pragma once
// Test helpers shared by cone_test.cpp and relaxed_cone_test.cpp: a tally of a registry
// technique (with parameter overrides) against `exact` on the contract harness's ray sets.
#include <support/ray_sets.h>

#include <relief/core/generators.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace relief::testing {

inline std::shared_ptr<const Surface> makeSurface(const char* generator, int w, int h,
                                                  EdgeMode edge, uint32_t seed = 1) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield(generator, w, h, seed));
    return std::make_shared<const Surface>(hf, 0.25f * float(w), edge);
}

struct ConeTally {
    size_t rays = 0, wrongHitMiss = 0, beyondTolerance = 0, pastFirstHit = 0;
    size_t falseHits = 0;  // hit where the reference misses (also in pastFirstHit)
    double maxError = 0.0;
    std::string describe(const std::string& what) const {
        return fmt::format("[ cone ] {}: rays {}, hit/miss differs {}, |dt|>1e-3 {}, past first "
                           "hit {}, max |dt| {:.3g}",
                           what, rays, wrongHitMiss, beyondTolerance, pastFirstHit, maxError);
    }
};

inline void tallyRays(const std::vector<Hit>& hits, const std::vector<Hit>& ref, ConeTally& t) {
    for (size_t k = 0; k < hits.size(); ++k) {
        ++t.rays;
        const Hit &h = hits[k], &r = ref[k];
        if (h.hit && r.hit) {
            const double e = std::abs(double(h.t) - double(r.t));
            t.maxError = std::max(t.maxError, e);
            if (e > 1e-3) ++t.beyondTolerance;
            if (h.t > r.t + 1e-4f) ++t.pastFirstHit;
        } else if (h.hit != r.hit) {
            ++t.wrongHitMiss;
            if (h.hit) ++t.pastFirstHit, ++t.falseHits;
        }
    }
}

// All standard generators, both edge modes, two sizes, as the contract harness.
inline ConeTally tallyAgainstExact(const char* technique,
                                   const std::vector<std::pair<std::string, double>>& params,
                                   int raysPerKind) {
    ConeTally tally;
    uint32_t seed = 1;
    for (const char* g : {"sine", "peaks6", "fbm", "walls", "spikes", "terraces", "ramp", "flat"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (ivec2 size : {ivec2(37, 23), ivec2(64, 64)}) {
                auto s = makeSurface(g, size.x, size.y, edge, seed);
                auto tracer = createTracer(technique, s, params);
                auto exact = createTracer("exact", s);
                if (!tracer.ok()) {
                    ADD_FAILURE() << tracer.error().message;
                    return tally;
                }
                RaySets sets(*s, seed++);
                const std::vector<Ray> rays = sets.all(raysPerKind);
                std::vector<Hit> hits(rays.size()), ref(rays.size());
                (*tracer)->traceBatch(rays, hits);
                (*exact)->traceBatch(rays, ref);
                tallyRays(hits, ref, tally);
            }
    return tally;
}

}  // namespace relief::testing
