// The sampled precomputation of §8 (precompute=1) against the exact one: it only sees a subset
// of the rays, so its distances are never shorter than the exact ones; it is approximate.
#include <gtest/gtest.h>

#include <support/safety_test_support.h>

#include <relief/techniques/registry.h>
#include <relief/techniques/safety_common/safety_sampled.h>

namespace relief::safety {
namespace {

TEST(SafetySampled, NeverShorterThanExactAndSometimesLonger) {
    size_t longer = 0, texels = 0;
    for (const char* gen : {"fig11", "fbm", "peaks6", "walls"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            auto s = testing::makeSurface(gen, 20, 16, edge, 0.25f);
            for (double phi : {90.0, -45.0}) {
                BuildOptions o;
                o.phiMaxDeg = phi;
                const DistanceMap exact = buildDistanceMap(*s, o);
                const DistanceMap sampled = buildSampledDistanceMap(*s, o);
                ASSERT_EQ(exact.r.size(), sampled.r.size());
                for (size_t k = 0; k < exact.r.size(); ++k) {
                    EXPECT_GE(sampled.r[k], exact.r[k]) << gen << " phi " << phi << " entry " << k;
                    longer += sampled.r[k] > exact.r[k];
                }
                texels += exact.r.size();
            }
        }
    std::printf("sampled distances longer than exact: %zu of %zu\n", longer, texels);
    EXPECT_GT(longer, 0u);  // the thin features of fig11 are what 8 x 256 rays miss
}

TEST(SafetySampled, RowsRefuseExteriorAndMismatchedBakes) {
    auto s = testing::makeSurface("fbm", 16, 16, EdgeMode::Clamp, 0.25f);
    const TechniqueInfo* sd = findTechnique("safety-sd");
    ASSERT_NE(sd, nullptr);
    auto make = [&](std::vector<std::pair<std::string, double>> params) {
        auto values = resolveParams(*sd, params);
        EXPECT_TRUE(values);
        return TechniqueInput{s, *values, nullptr};
    };
    auto exterior = sd->create(make({{"precompute", 1}, {"exterior", 1}}));
    ASSERT_FALSE(exterior);
    EXPECT_EQ(exterior.error().kind, ErrorKind::Unsupported);
    auto baked = sd->buildMaps(make({{"precompute", 1}}));
    ASSERT_TRUE(baked) << baked.error().message;
    TechniqueInput asExact = make({});
    asExact.maps = &*baked;
    EXPECT_FALSE(sd->create(asExact));
    TechniqueInput asSampled = make({{"precompute", 1}});
    asSampled.maps = &*baked;
    EXPECT_TRUE(sd->create(asSampled));
    EXPECT_EQ(contractOf(*sd, asSampled.params), Contract::Approximate);
}

}  // namespace
}  // namespace relief::safety
