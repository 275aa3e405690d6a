#pragma once
// The contract harness (DESIGN §3), shared by tests/contract_test.cpp (every registry row) and the
// toy-technique test (a row registered at start-up): a row traced against the reference on random
// and adversarial rays over all standard generators, both edge modes and odd sizes.
// exact → same hit/miss and |Δt| ≤ 1e-3; conservative → never past the first hit (t ≤ t_ref +
// 1e-4) and converged within 1e-3; approximate → statistics are recorded.
#include <support/ray_sets.h>

#include <relief/core/generators.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace relief::testing {

struct MapCase {
    const char* generator;
    int width, height;
    EdgeMode edge;
};

inline std::vector<MapCase> contractMapCases() {
    std::vector<MapCase> cases;
    for (const char* g : {"sine", "peaks6", "fbm", "walls", "spikes", "terraces", "ramp", "flat"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            cases.push_back({g, 37, 23, edge});
            cases.push_back({g, 64, 64, edge});
        }
    return cases;
}

struct Tally {
    size_t rays = 0, wrongHitMiss = 0, beyondTolerance = 0, pastFirstHit = 0;
    double maxError = 0.0, sumError = 0.0;
    size_t bothHit = 0;
};

inline void check(const TechniqueInfo& info, const Ray& ray, const Hit& h, const Hit& ref, Tally& tally) {
    ++tally.rays;
    if (h.hit && ref.hit) {
        const double e = std::abs(double(h.t) - double(ref.t));
        // Tolerances never below a few float ulps of t: with a very large depth (t in the
        // thousands) no float tracer can do better; for t < ~200 they are the fixed ones.
        const double ulps = 4.0 * std::numeric_limits<float>::epsilon() * std::abs(double(ref.t));
        ++tally.bothHit;
        tally.sumError += e;
        tally.maxError = std::max(tally.maxError, e);
        if (e > std::max(1e-3, ulps)) ++tally.beyondTolerance;
        if (double(h.t) > double(ref.t) + std::max(1e-4, ulps)) ++tally.pastFirstHit;
    } else if (h.hit != ref.hit) {
        ++tally.wrongHitMiss;
        if (h.hit && !ref.hit) ++tally.pastFirstHit;
    }
    if (h.hit) {
        EXPECT_TRUE(std::isfinite(h.t) && h.t >= 0.0f) << info.name;
        EXPECT_LT(glm::length(h.position - ray.at(h.t)), 1e-3f * std::max(1.0f, h.t)) << info.name;
    }
}

// check, printing each ray on which an exact or conservative row breaks its contract (bit-exact
// floats, so that the ray can be replayed and judged against the double-precision brute force).
inline void checkAndReport(const TechniqueInfo& info, Contract contract, const Ray& ray,
                           const Hit& h, const Hit& ref, Tally& tally) {
    const Tally before = tally;
    check(info, ray, h, ref, tally);
    if (contract != Contract::Approximate &&
        (tally.wrongHitMiss != before.wrongHitMiss || tally.pastFirstHit != before.pastFirstHit))
        std::printf("  %s ray o=(%a, %a, %a) d=(%a, %a, %a): hit %d t %.9g, exact hit %d t %.9g\n",
                    std::string(info.name).c_str(), ray.origin.x, ray.origin.y, ray.origin.z, ray.direction.x,
                    ray.direction.y, ray.direction.z, h.hit, h.t, ref.hit, ref.t);
}

// What the harness found for one row and parameter set.
struct ContractRun {
    Contract contract = Contract::Approximate;  // contractOf(row, parameters)
    Tally tally = {};
    std::vector<std::string> brokenOn = {};  // "fbm 64x64 clamp": map cases where the contract broke
    std::string error = {};                  // a tracer could not be made
};

// Traces `tracer` and the reference on `count` rays of `surface` (seeded), adding to `run` and
// naming `label` in run.brokenOn where the contract broke.
inline void traceCase(const TechniqueInfo& info, std::shared_ptr<const Surface> surface,
                      const Tracer& tracer, uint32_t seed, size_t count, const std::string& label,
                      ContractRun& run) {
    auto reference = createTracer(referenceTechnique().name, surface);
    RaySets sets(*surface, seed);
    const std::vector<Ray> rays = sets.all(count);
    std::vector<Hit> hits(rays.size()), referenceHits(rays.size());
    tracer.traceBatch(rays, hits);
    (*reference)->traceBatch(rays, referenceHits);
    const Tally before = run.tally;
    for (size_t k = 0; k < rays.size(); ++k)
        checkAndReport(info, run.contract, rays[k], hits[k], referenceHits[k], run.tally);
    if (run.contract != Contract::Approximate &&
        (run.tally.wrongHitMiss != before.wrongHitMiss || run.tally.pastFirstHit != before.pastFirstHit))
        run.brokenOn.push_back(label);
}

inline void printRun(const TechniqueInfo& info, const ContractRun& run) {
    const Tally& t = run.tally;
    std::printf("[ contract ] %-18s %-12s rays %zu, hit/miss differs %zu, |dt|>1e-3 %zu, "
                "past first hit %zu, mean |dt| %.3g, max |dt| %.3g\n",
                std::string(info.name).c_str(), std::string(toString(run.contract)).c_str(), t.rays,
                t.wrongHitMiss, t.beyondTolerance, t.pastFirstHit,
                t.bothHit ? t.sumError / double(t.bothHit) : 0.0, t.maxError);
}

// Traces the row with these overrides and the reference on 1200 rays per map case (with
// `clampOnly`, for forms that exist only in clamp mode: twice as many on the clamp cases; with
// `oddSizesOnly`, the 37x23 cases only, twice as many again: the same ray count on a fifth of
// the texels, for forms whose maps cost most of the run to bake).
inline ContractRun runContractHarness(const TechniqueInfo& info,
                                      const std::vector<std::pair<std::string, double>>& overrides = {},
                                      bool clampOnly = false, bool oddSizesOnly = false) {
    ContractRun run;
    auto params = resolveParams(info, overrides);
    if (!params) return {.error = params.error().message};
    run.contract = contractOf(info, *params);
    const int raysPerCase = 1200 * (clampOnly ? 2 : 1) * (oddSizesOnly ? 2 : 1);
    uint32_t seed = 1;
    for (const MapCase& c : contractMapCases()) {
        if (clampOnly && c.edge != EdgeMode::Clamp) continue;
        if (oddSizesOnly && c.width == c.height) continue;
        auto hf = std::make_shared<const Heightfield>(
            *generateHeightfield(c.generator, c.width, c.height, seed));
        auto surface = std::make_shared<const Surface>(hf, 0.25f * float(c.width), c.edge);
        auto tracer = createTracer(info.name, surface, overrides);
        if (!tracer) return {.error = tracer.error().message};
        traceCase(info, surface, **tracer, seed++, raysPerCase,
                  fmt::format("{} {}x{} {}", c.generator, c.width, c.height, toString(c.edge)),
                  run);
    }
    printRun(info, run);
    return run;
}

// The contract's promise, on a harness run (DESIGN §3).
inline bool keepsContract(const ContractRun& run) {
    const Tally& t = run.tally;
    switch (run.contract) {
        case Contract::Exact: return t.wrongHitMiss == 0 && t.beyondTolerance == 0;
        case Contract::Conservative:
            return t.pastFirstHit == 0 && t.wrongHitMiss == 0 && t.beyondTolerance == 0;
        case Contract::Approximate: return true;  // recorded; the bench reports it
    }
    return false;
}

}  // namespace relief::testing
