// safety-cc: the safety rows' cases (support/safety_tracer_cases.h) with this row's traits, and
// its exterior-ray maps (cyl_ext with cone_all or cone_ext slopes): exact from exterior views,
// interior origins on the exact walk, repeat mode refused.
#include <support/safety_tracer_cases.h>

#include <relief/techniques/safety_cc/safety_cc.h>

namespace relief::safety_cases {

struct Cc : Row<SafetyCcTracer, makeSafetyCcTracer, buildSafetyCcMaps, kSafetyCcParams> {
    static constexpr const char* kName = "safety-cc";
};
INSTANTIATE_TYPED_TEST_SUITE_P(SafetyCc, SafetyTracer, Cc);

namespace {

auto exteriorCc(std::vector<std::pair<std::string, double>> params) {
    params.emplace_back("exterior", 1);
    return [params](std::shared_ptr<const Surface> s) {
        return *makeSafetyCcTracer(inputFor(std::move(s), params, kSafetyCcParams));
    };
}

TEST(SafetyExterior, ExactFromExteriorViewsCc) {
    exactFromExteriorViews("CC cyl_ext + cone_all", exteriorCc({}));
    exactFromExteriorViews("CC cyl_ext + cone_ext", exteriorCc({{"exterior-slope", 1}}));
    exactFromExteriorViews("CC cone_ext phi-max -45",
                           exteriorCc({{"exterior-slope", 1}, {"phi-max", -45}}), -45.0);
}

TEST(SafetyExterior, InteriorOriginsStayExactCc) {
    interiorOriginsStayExact(exteriorCc({{"exterior-slope", 1}}), true);
}

TEST(SafetyExterior, RepeatModeRefusedCc) {
    auto tiled = makeSurface("walls", 24, 20, EdgeMode::Repeat, 0.25f);
    EXPECT_FALSE(buildSafetyCcMaps(inputFor(tiled, {{"exterior", 1}}, kSafetyCcParams)));
}

}  // namespace
}  // namespace relief::safety_cases
