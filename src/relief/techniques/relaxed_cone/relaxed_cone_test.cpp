// relaxed-cone (the published map): measured against the reference; it steps over thin walls that
// the safe strict cones of `cone` do not, on the same rays; shadow rays are exact.
#include <support/cone_test_support.h>

#include <relief/techniques/relaxed_cone/relaxed_cone.h>

#include <gtest/gtest.h>

namespace relief {
namespace {

using testing::ConeTally;

TEST(RelaxedConeTracer, PublishedIsMeasured) {
    const ConeTally tally = testing::tallyAgainstExact("relaxed-cone", {}, 1200);
    std::printf("%s\n", tally.describe("relaxed-cone faithful").c_str());
    EXPECT_GE(tally.rays, 100000u);
}

// Descending rays over `walls` from outside the box: the published map steps over walls (a hit
// past the first one, or a miss where there is a hit); the safe strict map (`cone` variant 0, the
// map the dropped strict-cone variant of relaxed-cone used) never does on the same rays.
TEST(RelaxedConeTracer, PublishedMissesWallsThatSafeConesDoNot) {
    const auto s = testing::makeSurface("walls", 64, 64, EdgeMode::Clamp, 3);
    testing::RaySets sets(*s, 3);
    std::vector<Ray> rays;
    for (const Ray& r : sets.fromOutside(100000))
        if (r.direction.z < 0.0f) rays.push_back(r);
    auto run = [&](const char* name, std::vector<std::pair<std::string, double>> params) {
        auto tracer = createTracer(name, s, params);
        EXPECT_TRUE(tracer.ok());
        std::vector<Hit> hits(rays.size());
        (*tracer)->traceBatch(rays, hits);
        return hits;
    };
    const auto ref = run("exact", {});
    const auto faithful = run("relaxed-cone", {{"max-steps", 200.0}});
    const auto safe = run("cone", {{"variant", 0.0}, {"max-steps", 200.0}});
    size_t faithfulPast = 0, safePast = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        auto past = [&](const Hit& h) {
            return ref[k].hit && (!h.hit || h.t > ref[k].t + 1e-4f);
        };
        faithfulPast += past(faithful[k]);
        safePast += past(safe[k]);
    }
    std::printf("[ relaxed walls ] %zu rays: faithful past/missed %zu, safe %zu\n", rays.size(),
                faithfulPast, safePast);
    EXPECT_GT(faithfulPast, 0u);
    EXPECT_EQ(safePast, 0u);
}

TEST(RelaxedConeTracer, ShadowRaysAreExact) {
    const auto s = testing::makeSurface("walls", 64, 64, EdgeMode::Clamp, 5);
    testing::RaySets sets(*s, 5);
    std::vector<Ray> rays;
    for (const Ray& r : sets.fromAboveSurface(20000))
        if (r.direction.z >= 0.0f) rays.push_back(r);
    auto relaxed = createTracer("relaxed-cone", s);
    auto exact = createTracer("exact", s);
    std::vector<Hit> h(rays.size()), r(rays.size());
    (*relaxed)->traceBatch(rays, h);
    (*exact)->traceBatch(rays, r);
    ConeTally tally;
    testing::tallyRays(h, r, tally);
    EXPECT_EQ(tally.wrongHitMiss, 0u);
    EXPECT_EQ(tally.beyondTolerance, 0u);
}

// Maps baked for the dropped strict-cone variant are refused with a message that says so.
TEST(RelaxedConeTracer, StrictVariantMapsAreRefused) {
    const auto s = testing::makeSurface("fbm", 16, 12, EdgeMode::Clamp);
    const TechniqueInfo& info = *findTechnique("relaxed-cone");
    auto params = resolveParams(info, {});
    auto maps = info.buildMaps(TechniqueInput{s, *params});
    ASSERT_TRUE(maps.ok());
    EXPECT_TRUE(info.create(TechniqueInput{s, *params, &*maps}).ok());
    TechniqueMaps strict = *maps;
    strict.parameters["variant"] = "0";
    auto refused = info.create(TechniqueInput{s, *params, &strict});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().kind, ErrorKind::InvalidInput);
    EXPECT_NE(refused.error().message.find("strict-cone"), std::string::npos);
    EXPECT_FALSE(info.check(TechniqueInput{s, *params, &strict}).ok());
}

}  // namespace
}  // namespace relief
