// maxmip against the reference (contract "exact").
#include <gtest/gtest.h>
#include <relief/techniques/maxmip/maxmip.h>
#include <support/walk_test_support.h>
#include <relief/techniques/registry.h>

namespace relief {
namespace {

auto maxmipMaker(WalkLimits limits = {}) {
    return [=](const std::shared_ptr<const Surface>& surface) {
        return MaxmipTracer(surface, std::make_shared<const MaxPyramid>(*surface), limits);
    };
}

TEST(Maxmip, ExactAgainstReference) {
    const auto tally = walk_test::contractOnAllMaps(maxmipMaker(), 300, "maxmip");
    EXPECT_GE(tally.rays, 100000u);
    EXPECT_EQ(tally.wrong, 0u);
}

// box-surface = 2: the walk over the texel-box pyramid is the texel-box reference's first hit.
TEST(Maxmip, TexelBoxesExactOnTheirSurface) {
    const auto tally = walk_test::contractOnAllMapsWith(
        [](const std::shared_ptr<const Surface>& surface) {
            return MaxmipTracer(
                surface, std::make_shared<const MaxPyramid>(MaxPyramid::overTexels(*surface)),
                {0, true});
        },
        [](const std::shared_ptr<const Surface>& s) { return walk_test::TexelBoxReference{s}; },
        300, "maxmip box-surface=2 vs texel boxes");
    EXPECT_GE(tally.rays, 100000u);
    EXPECT_EQ(tally.wrong, 0u);
}

TEST(Maxmip, CappedCursorNeverPassesFirstHit) {
    walk_test::cursorNeverPassesFirstHit(
        [](const std::shared_ptr<const Surface>& surface, int cap) {
            return maxmipMaker({cap, false})(surface);
        },
        "maxmip");
}

// Ascending to the common ancestor: a low, nearly level ray over sparse spikes does not walk
// cell by cell after a cell test; it climbs back to big nodes.
TEST(Maxmip, ClimbsBackAfterACellTest) {
    const auto surface = walk_test::makeSurface({"spikes", 512, 512, EdgeMode::Clamp, 0.05f});
    const auto tracer = maxmipMaker()(surface);
    const Ray ray{vec3(0.0f, 100.3f, 25.0f), glm::normalize(vec3(1.0f, 0.0f, -0.001f)), kInfinity};
    const Hit hit = tracer.trace(ray);
    const Hit ref = testing::ReferenceTracer(surface).trace(ray);
    EXPECT_EQ(hit.hit, ref.hit);
    EXPECT_LT(hit.steps, ref.steps);
}

TEST(Maxmip, RegistryRow) {
    const TechniqueInfo* info = findTechnique("maxmip");
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->contract, Contract::Exact);
}

}  // namespace
}  // namespace relief
