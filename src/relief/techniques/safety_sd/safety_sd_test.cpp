// safety-sd: the safety rows' cases (support/safety_tracer_cases.h) with this row's traits, and
// its exterior-ray maps: exact from exterior views, interior origins on the exact walk, maps that
// cannot serve refused.
#include <support/safety_tracer_cases.h>

#include <relief/techniques/safety_sd/safety_sd.h>

namespace relief::safety_cases {

struct Sd : Row<SafetySdTracer, makeSafetySdTracer, buildSafetySdMaps, kSafetySdParams> {
    static constexpr const char* kName = "safety-sd";
};
INSTANTIATE_TYPED_TEST_SUITE_P(SafetySd, SafetyTracer, Sd);

namespace {

SafetySdTracer exteriorSd(std::shared_ptr<const Surface> s) {
    return *makeSafetySdTracer(inputFor(std::move(s), {{"exterior", 1}}, kSafetySdParams));
}

TEST(SafetyExterior, ExactFromExteriorViewsSd) {
    exactFromExteriorViews("SD exterior", exteriorSd);
}

TEST(SafetyExterior, InteriorOriginsStayExactSd) { interiorOriginsStayExact(exteriorSd, true); }

TEST(SafetyExterior, UnusableMapsRefusedSd) {
    auto s = makeSurface("walls", 24, 20, EdgeMode::Clamp, 0.25f);
    // All-ray maps asked for exterior: refused.
    const TechniqueMaps allRays =
        safety::distanceMapToArrays("safety-sd", safety::buildDistanceMap(*s, {}), {});
    TechniqueInput exterior = inputFor(s, {{"exterior", 1}}, kSafetySdParams);
    exterior.maps = &allRays;
    EXPECT_FALSE(makeSafetySdTracer(exterior));
    // Repeat mode: refused.
    auto tiled = makeSurface("walls", 24, 20, EdgeMode::Repeat, 0.25f);
    EXPECT_FALSE(makeSafetySdTracer(inputFor(tiled, {{"exterior", 1}}, kSafetySdParams)));
}

}  // namespace
}  // namespace relief::safety_cases
