// safety-sd and safety-cc (one typed suite): the contract for the parameter variants the generic
// harness does not cover (isotropic, φ_max, baked maps), shadow rays, and the measured error of
// the §7 options.
#include <support/safety_test_support.h>

#include <relief/techniques/registry.h>
#include <relief/techniques/safety_cc/safety_cc.h>
#include <relief/techniques/safety_sd/safety_sd.h>

namespace relief {
namespace {

using safety::testing::contractOnAllMaps;
using safety::testing::inputFor;
using safety::testing::makeSurface;
using safety::testing::Tally;

struct Sd {
    using Tracer = SafetySdTracer;
    static constexpr const char* kName = "safety-sd";
    static auto make(const TechniqueInput& input) { return makeSafetySdTracer(input); }
    static auto build(const TechniqueInput& input) { return buildSafetySdMaps(input); }
    static constexpr std::span<const ParamSpec> params() { return kSafetySdParams; }
};
struct Cc {
    using Tracer = SafetyCcTracer;
    static constexpr const char* kName = "safety-cc";
    static auto make(const TechniqueInput& input) { return makeSafetyCcTracer(input); }
    static auto build(const TechniqueInput& input) { return buildSafetyCcMaps(input); }
    static constexpr std::span<const ParamSpec> params() { return kSafetyCcParams; }
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

std::string label(const char* technique, const std::string& what) {
    return std::string(technique) + " " + what;
}

template <class T>
class SafetyTracer : public ::testing::Test {};
using SafetyTechniques = ::testing::Types<Sd, Cc>;
TYPED_TEST_SUITE(SafetyTracer, SafetyTechniques);

TYPED_TEST(SafetyTracer, ExactIsotropic) {
    using T = TypeParam;
    const Tally t = contractOnAllMaps(maker<T>({{"isotropic", 1}}), 1200,
                                      label(T::kName, "isotropic").c_str());
    EXPECT_GE(t.rays, 100000u);
    EXPECT_EQ(t.wrong + t.beyond, 0u);
}

// Rays outside φ_max take the exact walk: still exact, and counted.
TYPED_TEST(SafetyTracer, ExactWithPhiMax) {
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

TYPED_TEST(SafetyTracer, ShadowRaysMatchExact) {
    using T = TypeParam;
    const Tally t = shadowRays(maker<T>({}), T::kName);
    EXPECT_EQ(t.wrong + t.beyond, 0u);
    EXPECT_GT(t.both, 1000u);  // plenty of occluded points
}

// §7 options are approximate: report their error, keep it small.
TYPED_TEST(SafetyTracer, ApproximateVariantsMeasured) {
    using T = TypeParam;
    for (const char* name : {"view-dependent", "positive-distance"}) {
        const Tally t = contractOnAllMaps(maker<T>({{name, 1}}), 1200,
                                          label(T::kName, std::string(name) + " (approx.)").c_str(),
                                          false);
        ::testing::Test::RecordProperty(name, std::to_string(t.wrong));
        EXPECT_LT(double(t.wrong + t.far), 0.05 * double(t.rays)) << name;
    }
}

TYPED_TEST(SafetyTracer, BakedMapsRoundTrip) {
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
TYPED_TEST(SafetyTracer, FewerStepsThanTheReferenceWithinPhiMax) {
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

TYPED_TEST(SafetyTracer, RegistryRow) {
    const TechniqueInfo* info = findTechnique(TypeParam::kName);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->contract, Contract::Exact);
    EXPECT_NE(info->buildMaps, nullptr);
}

}  // namespace
}  // namespace relief
