// cone: map invariants against dense sampling of S and brute force, and the tracer's contract
// for the variants and encodings the generic harness (tests/contract_test.cpp) does not cover.
#include <support/cone_test_support.h>

#include <relief/techniques/cone/cone.h>

#include <gtest/gtest.h>

namespace relief {
namespace {

using testing::ConeTally;
using testing::tallyAgainstExact;

// No point of S strictly inside K = {dist(xy, F) ≤ c·(z − a)}: S sampled on a fine grid.
void expectFrustumEmpty(const Surface& s, const std::vector<vec2>& cones) {
    const int n = 8;  // samples per texel and axis
    size_t violations = 0;
    for (int j = 0; j < s.height(); ++j)
        for (int i = 0; i < s.width(); ++i) {
            const vec2 cone = cones[size_t(j) * size_t(s.width()) + size_t(i)];
            for (int y = -2 * n; y < (s.height() + 2) * n; ++y)
                for (int x = -2 * n; x < (s.width() + 2) * n; ++x) {
                    const float px = (float(x) + 0.5f) / float(n), py = (float(y) + 0.5f) / float(n);
                    if (s.edge() == EdgeMode::Clamp &&
                        (px < 0 || py < 0 || px > float(s.width()) || py > float(s.height())))
                        continue;
                    const float dx = std::max({0.0f, float(i) - px, px - float(i + 1)});
                    const float dy = std::max({0.0f, float(j) - py, py - float(j + 1)});
                    const float z = s.heightAt(px, py);
                    if (std::sqrt(dx * dx + dy * dy) < cone.y * (z - cone.x) - 1e-4f) ++violations;
                }
        }
    EXPECT_EQ(violations, 0u);
}

TEST(ConeMap, SafeFrustumHoldsNoPointOfS) {
    for (const char* g : {"fbm", "walls", "spikes", "terraces", "peaks6"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            const auto s = testing::makeSurface(g, 12, 9, edge);
            SCOPED_TRACE(std::string(g) + " " + std::string(toString(edge)));
            expectFrustumEmpty(*s, buildCones(*s, ConeKind::SafeStrict));
        }
}

TEST(ConeMap, PyramidSearchEqualsBruteForce) {
    for (ConeKind kind : {ConeKind::SafeStrict, ConeKind::FaithfulStrict, ConeKind::FaithfulRelaxed})
        for (const char* g : {"fbm", "walls", "terraces"})
            for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
                const auto s = testing::makeSurface(g, 13, 10, edge);
                const auto fast = buildCones(*s, kind), brute = buildConesBruteForce(*s, kind);
                ASSERT_EQ(fast.size(), brute.size());
                for (size_t k = 0; k < fast.size(); ++k) {
                    ASSERT_EQ(fast[k].x, brute[k].x) << g << " texel " << k;
                    ASSERT_NEAR(fast[k].y, brute[k].y, 1e-5f * (1.0f + brute[k].y))
                        << g << " " << int(kind) << " texel " << k;
                }
            }
}

// The pruned search (warm start from the neighbour, start level, pruning margin) returns the
// brute force's minimum to the bit, on maps large enough for the pyramid to have several levels
// above the start level and for rows to hand guesses to each other.
TEST(ConeMap, PyramidSearchEqualsBruteForceToTheBit) {
    struct Case {
        const char* generator;
        int w, h;
        EdgeMode edge;
    };
    for (ConeKind kind : {ConeKind::SafeStrict, ConeKind::FaithfulStrict, ConeKind::FaithfulRelaxed})
        for (const Case& c : {Case{"fbm", 45, 38, EdgeMode::Clamp},
                              Case{"terraces", 40, 33, EdgeMode::Clamp},
                              Case{"peaks6", 21, 17, EdgeMode::Repeat}}) {
            const auto s = testing::makeSurface(c.generator, c.w, c.h, c.edge, 7);
            const auto fast = buildCones(*s, kind), brute = buildConesBruteForce(*s, kind);
            size_t differ = 0;
            for (size_t k = 0; k < fast.size(); ++k)
                differ += fast[k].x != brute[k].x || fast[k].y != brute[k].y;
            EXPECT_EQ(differ, 0u) << c.generator << " kind " << int(kind);
        }
}

// The relaxed search skips the walks its slope bound proves empty: on maps large enough for most
// candidate rays to be skipped, the map is the one the full walks give, to the bit.
TEST(ConeMap, RelaxedWalkSkipChangesNothing) {
    for (const char* g : {"fbm", "peaks6", "walls"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            const auto s = testing::makeSurface(g, 96, 80, edge, 3);
            const auto skipped = buildCones(*s, ConeKind::FaithfulRelaxed, true);
            const auto walked = buildCones(*s, ConeKind::FaithfulRelaxed, false);
            size_t differ = 0;
            for (size_t k = 0; k < skipped.size(); ++k)
                differ += skipped[k].x != walked[k].x || skipped[k].y != walked[k].y;
            EXPECT_EQ(differ, 0u) << g << " edge " << int(edge);
        }
}

TEST(ConeMap, QuantizationNeverWidens) {
    const auto s = testing::makeSurface("fbm", 32, 32, EdgeMode::Clamp);
    const auto cones = buildCones(*s, ConeKind::SafeStrict);
    for (int bits : {8, 16})
        for (bool sq : {false, true}) {
            const ConeEncoding e{bits, sq};
            const ConeMap m = decodeCones(*s, encodeCones(*s, cones, e), e);
            for (size_t k = 0; k < cones.size(); ++k) {
                EXPECT_GE(m.texels()[k].x, cones[k].x) << bits << " " << sq;
                EXPECT_LE(m.texels()[k].y, cones[k].y) << bits << " " << sq;
            }
        }
}

TEST(ConeTracer, SafeIsConservativeForEveryEncoding) {
    for (double bits : {32.0, 16.0, 8.0})
        for (double sq : {0.0, 1.0}) {
            const ConeTally tally =
                tallyAgainstExact("cone", {{"bits", bits}, {"sqrt", sq}}, 1200);
            SCOPED_TRACE(tally.describe(
                "cone bits=" + std::to_string(int(bits)) + " sqrt=" + std::to_string(int(sq))));
            EXPECT_GE(tally.rays, 100000u);
            EXPECT_EQ(tally.pastFirstHit, 0u);
            EXPECT_EQ(tally.wrongHitMiss, 0u);
            EXPECT_EQ(tally.beyondTolerance, 0u);
        }
}

TEST(ConeTracer, FaithfulIsMeasured) {
    const ConeTally tally = tallyAgainstExact("cone", {{"variant", 1.0}}, 1200);
    std::printf("%s\n", tally.describe("cone faithful").c_str());
    EXPECT_GE(tally.rays, 100000u);
}

TEST(ConeTracer, RefusesMapsBakedWithOtherParameters) {
    const auto s = testing::makeSurface("fbm", 16, 16, EdgeMode::Clamp);
    const TechniqueInfo& info = *findTechnique("cone");
    auto params = resolveParams(info, {{"bits", 8.0}});
    ASSERT_TRUE(params.ok());
    auto maps = info.buildMaps(TechniqueInput{s, *params});
    ASSERT_TRUE(maps.ok());
    auto same = info.create(TechniqueInput{s, *params, &*maps});
    EXPECT_TRUE(same.ok());
    auto other = resolveParams(info, {{"bits", 16.0}});
    auto refused = info.create(TechniqueInput{s, *other, &*maps});
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("bits"), std::string::npos);
    TechniqueMaps broken = *maps;
    broken.arrays[0].width = 3;
    EXPECT_FALSE(info.create(TechniqueInput{s, *params, &broken}).ok());
}

}  // namespace
}  // namespace relief
