#pragma once
// The cases both safety rows must pass (one typed suite, instantiated with the row's traits by
// safety_sd/safety_sd_test.cpp and safety_cc/safety_cc_test.cpp): the contract for the parameter
// variants the generic harness does not cover (isotropic, φ_max, baked maps), shadow rays, the
// measured error of the §7 options, and exact rendering from exterior views (exterior maps).
#include <support/safety_test_support.h>

#include <relief/techniques/registry.h>

namespace relief::safety_cases {

using safety::testing::contractOnAllMaps;
using safety::testing::inputFor;
using safety::testing::makeSurface;
using safety::testing::Tally;

// A row's traits (add `static constexpr const char* kName`).
template <class TracerType, auto kMake, auto kBuild, const std::span<const ParamSpec>& kParams>
struct Row {
    using Tracer = TracerType;
    static auto make(const TechniqueInput& input) { return kMake(input); }
    static auto build(const TechniqueInput& input) { return kBuild(input); }
    static constexpr std::span<const ParamSpec> params() { return kParams; }
};

template <class T>
TechniqueInput input(std::shared_ptr<const Surface> s,
                     std::vector<std::pair<std::string, double>> params) {
    return inputFor(std::move(s), params, T::params());
}

template <class T>
auto maker(std::vector<std::pair<std::string, double>> params) {
    return [=](std::shared_ptr<const Surface> s) { return *T::make(input<T>(std::move(s), params)); };
}

inline std::string label(const char* technique, const std::string& what) {
    return std::string(technique) + " " + what;
}

template <class T>
class SafetyTracer : public ::testing::Test {};
TYPED_TEST_SUITE_P(SafetyTracer);

TYPED_TEST_P(SafetyTracer, ExactIsotropic) {
    using T = TypeParam;
    const Tally t = contractOnAllMaps(maker<T>({{"isotropic", 1}}), 1200,
                                      label(T::kName, "isotropic").c_str());
    EXPECT_GE(t.rays, 100000u);
    EXPECT_EQ(t.wrong + t.beyond, 0u);
}

// Rays outside φ_max take the exact walk: still exact, and counted.
TYPED_TEST_P(SafetyTracer, ExactWithPhiMax) {
    using T = TypeParam;
    for (double phi : {-45.0, 30.0}) {
        const Tally t = contractOnAllMaps(maker<T>({{"phi-max", phi}}), 1200,
                                          label(T::kName, phi < 0 ? "phi-max -45" : "phi-max 30").c_str());
        EXPECT_GE(t.rays, 100000u);
        EXPECT_EQ(t.wrong + t.beyond, 0u);
    }
    auto s = makeSurface("fbm", 32, 32, EdgeMode::Clamp, 0.25f);
    const typename T::Tracer tracer = *T::make(input<T>(s, {{"phi-max", -45}}));
    const Ray shallow{vec3(-1, 16, 9), glm::normalize(vec3(1, 0.1f, -0.3f)), kInfinity};
    const Ray steep{vec3(10, 16, 9), glm::normalize(vec3(1, 0.1f, -3.0f)), kInfinity};
    tracer.trace(shallow);
    tracer.trace(steep);
    EXPECT_EQ(tracer.fallbacks(), 1u);
    EXPECT_FALSE(safety::viewWithinPhiMax(std::span(&shallow, 1), -45.0));
    EXPECT_TRUE(safety::viewWithinPhiMax(std::span(&steep, 1), -45.0));
    EXPECT_TRUE(safety::viewWithinPhiMax(std::span(&shallow, 1), 90.0));
}

// Shadow rays: from points on S toward lights above the horizon (upward rays), hit = occluded.
template <class Make>
Tally shadowRays(Make make, const char* label) {
    Tally all;
    std::mt19937 rng(3);
    auto u = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
    for (const char* gen : {"fbm", "walls", "peaks6", "fig11"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            auto s = makeSurface(gen, 48, 40, edge, 0.25f);
            const auto tracer = make(s);
            std::vector<Ray> rays;
            for (int k = 0; k < 4000; ++k) {
                const float x = u(0, 48), y = u(0, 40);
                const float el = glm::radians(u(2.0f, 60.0f)), az = u(0.0f, 6.2832f);
                const vec3 light(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
                rays.push_back(Ray{vec3(x, y, s->heightAt(x, y) + 1e-3f), light, kInfinity});
            }
            const Tally t = safety::testing::tally(tracer, *s, rays);
            EXPECT_EQ(t.wrong, 0u) << label << " " << gen << " " << toString(edge);
            all.add(t);
        }
    std::printf("[ safety   ] %s shadow rays %zu, hit/miss differs %zu, occluded %zu\n", label,
                all.rays, all.wrong, all.both);
    return all;
}

TYPED_TEST_P(SafetyTracer, ShadowRaysMatchExact) {
    using T = TypeParam;
    const Tally t = shadowRays(maker<T>({}), T::kName);
    EXPECT_EQ(t.wrong + t.beyond, 0u);
    EXPECT_GT(t.both, 1000u);  // plenty of occluded points
}

// §7 options are approximate: report their error, keep it small.
TYPED_TEST_P(SafetyTracer, ApproximateVariantsMeasured) {
    using T = TypeParam;
    for (const char* name : {"view-dependent", "positive-distance"}) {
        const Tally t = contractOnAllMaps(maker<T>({{name, 1}}), 1200,
                                          label(T::kName, std::string(name) + " (approx.)").c_str(),
                                          false);
        ::testing::Test::RecordProperty(name, std::to_string(t.wrong));
        EXPECT_LT(double(t.wrong + t.far), 0.05 * double(t.rays)) << name;
    }
}

TYPED_TEST_P(SafetyTracer, BakedMapsRoundTrip) {
    using T = TypeParam;
    auto s = makeSurface("walls", 40, 30, EdgeMode::Repeat, 0.25f);
    const TechniqueInput restricted = input<T>(s, {{"phi-max", -30}});
    auto maps = T::build(restricted);
    ASSERT_TRUE(maps.ok());
    EXPECT_EQ(maps->parameters.at("phi-max"), "-30");
    TechniqueInput fromMaps = input<T>(s, {});
    fromMaps.maps = &*maps;
    const typename T::Tracer baked = *T::make(fromMaps);
    const typename T::Tracer built = *T::make(restricted);
    EXPECT_EQ(baked.options().phiMaxDeg, -30.0);
    ::relief::testing::RaySets sets(*s, 9);
    for (const Ray& r : sets.all(300)) {
        const Hit a = baked.trace(r), b = built.trace(r);
        ASSERT_EQ(a.hit, b.hit);
        ASSERT_EQ(a.steps, b.steps);
    }
    TechniqueInput other = input<T>(s, {{"phi-max", 10}});
    other.maps = &*maps;
    EXPECT_FALSE(T::make(other).ok());
    TechniqueMaps broken = *maps;
    broken.arrays[0].data.pop_back();
    fromMaps.maps = &broken;
    EXPECT_FALSE(T::make(fromMaps).ok());
}

// With all rays allowed, fbm at this depth leaves mostly r = 0 (the walk is then about the
// naive one); restricted to steep views (φ_max = −45°) the distances grow and steps drop.
TYPED_TEST_P(SafetyTracer, FewerStepsThanTheReferenceWithinPhiMax) {
    using T = TypeParam;
    auto s = makeSurface("fbm", 256, 256, EdgeMode::Clamp, 0.1f);
    const typename T::Tracer all = *T::make(input<T>(s, {}));
    const typename T::Tracer steep = *T::make(input<T>(s, {{"phi-max", -45}}));
    const relief::testing::ReferenceTracer exact(s);
    ::relief::testing::RaySets sets(*s, 4);
    size_t steps = 0, stepsAll = 0, reference = 0, rays = 0;
    for (const Ray& r : sets.fromOutside(4000)) {
        if (!safety::rayWithinPhiMax(r.direction, safety::tanPhiMax(-45))) continue;
        steps += size_t(steep.trace(r).steps);
        stepsAll += size_t(all.trace(r).steps);
        reference += size_t(exact.trace(r).steps);
        ++rays;
    }
    std::printf("[ safety   ] fbm 256^2, %zu steep rays: %s %.1f steps/ray (phi-max -45), "
                "%.1f (all rays), exact %.1f\n", rays, T::kName, double(steps) / rays,
                double(stepsAll) / rays, double(reference) / rays);
    EXPECT_EQ(steep.fallbacks(), 0u);
    EXPECT_LT(steps, reference);
}

TYPED_TEST_P(SafetyTracer, RegistryRow) {
    const TechniqueInfo* info = findTechnique(TypeParam::kName);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->contract, Contract::Exact);
    EXPECT_NE(info->buildMaps, nullptr);
}

// ---- Exterior maps (§6.2): rendering from exterior views, interior origins ----

// Exterior views of seven reliefs are exact; the only fallbacks are rays outside φ_max.
template <class Make>
void exactFromExteriorViews(const char* label, Make make, double phiMax = 90.0) {
    uint32_t seed = 41;
    size_t total = 0;
    for (const char* g : {"walls", "spikes", "fig11", "fbm", "terraces", "peaks6", "sine"}) {
        auto s = makeSurface(g, 48, 40, EdgeMode::Clamp, 0.25f);
        const auto tracer = make(s);
        ::relief::testing::RaySets sets(*s, seed++);
        std::vector<Ray> rays = sets.fromOutside(90000);
        std::mt19937 rng(seed);
        for (const Ray& r : safety::testing::exteriorRays(*s, 20000, rng)) rays.push_back(r);
        const auto t = safety::testing::tally(tracer, *s, rays);
        EXPECT_EQ(t.wrong, 0u) << label << " " << g;
        EXPECT_EQ(t.beyond, 0u) << label << " " << g;
        size_t outsidePhi = 0;  // the only fallbacks: every origin is exterior
        for (const Ray& r : rays)
            outsidePhi += !s->clip(r).empty() &&
                          !safety::rayWithinPhiMax(r.direction, safety::tanPhiMax(phiMax));
        EXPECT_EQ(tracer.fallbacks(), outsidePhi) << label << " " << g;
        total += t.rays;
        std::printf("[ safety   ] %-28s %-8s rays %zu, hit/miss differs %zu, |dt|>1e-3 %zu, "
                    "max |dt| %.3g\n", label, g, t.rays, t.wrong, t.beyond, t.maxError);
    }
    EXPECT_GE(total, size_t(7e5));
}

// Shadow rays and cameras inside the box: the exterior maps are not used, the exact walk is
// (`countsFallbacks`: and each such ray is counted).
template <class Make>
void interiorOriginsStayExact(Make make, bool countsFallbacks) {
    for (const char* g : {"walls", "spikes", "fig11", "fbm"}) {
        auto s = makeSurface(g, 48, 40, EdgeMode::Clamp, 0.25f);
        ::relief::testing::RaySets sets(*s, 5);
        const std::vector<Ray> rays = sets.fromAboveSurface(20000);
        const auto tracer = make(s);
        const auto t = safety::testing::tally(tracer, *s, rays);
        EXPECT_EQ(t.wrong, 0u) << g;
        EXPECT_EQ(t.beyond, 0u) << g;
        if (countsFallbacks) {
            EXPECT_GT(tracer.fallbacks(), 0u) << g;
        }
    }
}

REGISTER_TYPED_TEST_SUITE_P(SafetyTracer, ExactIsotropic, ExactWithPhiMax, ShadowRaysMatchExact,
                            ApproximateVariantsMeasured, BakedMapsRoundTrip,
                            FewerStepsThanTheReferenceWithinPhiMax, RegistryRow);

}  // namespace relief::safety_cases
