// quadtree against the reference (contract "exact"), and the approximate options.
#include <gtest/gtest.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <support/walk_test_support.h>
#include <relief/techniques/registry.h>

namespace relief {
namespace {

using walk_test::MapSpec;

auto quadtreeMaker(Ascent ascent, WalkLimits limits = {}) {
    return [=](const std::shared_ptr<const Surface>& surface) {
        return QuadtreeTracer(surface, std::make_shared<const MaxPyramid>(*surface), ascent,
                              limits);
    };
}

TEST(Quadtree, ExactAgainstReference) {
    const auto tally = walk_test::contractOnAllMaps(quadtreeMaker(Ascent::Parent), 300, "quadtree");
    EXPECT_GE(tally.rays, 100000u);
    EXPECT_EQ(tally.wrong, 0u);
}

TEST(Quadtree, PaperAscentIsExactToo) {
    const auto tally =
        walk_test::contractOnAllMaps(quadtreeMaker(Ascent::None), 60, "quadtree ascend=0");
    EXPECT_EQ(tally.wrong, 0u);
}

TEST(Quadtree, FixedLoopCursorNeverPassesFirstHit) {
    walk_test::cursorNeverPassesFirstHit(
        [](const std::shared_ptr<const Surface>& surface, int cap) {
            return quadtreeMaker(Ascent::Parent, {cap, false})(surface);
        },
        "quadtree");
}

TEST(Quadtree, HugeCapIsExact) {
    const auto tally = walk_test::contractOnAllMaps(quadtreeMaker(Ascent::Parent, {1000000, false}),
                                                    20, "quadtree max-steps=1e6");
    EXPECT_EQ(tally.wrong, 0u);
}

// Cell boxes at the corner maximum contain S: never later than the first hit, never a miss
// where S is hit.
TEST(Quadtree, BoxSurfaceIsNeverBehindS) {
    for (const MapSpec& m : walk_test::contractMaps()) {
        const auto surface = walk_test::makeSurface(m, 2);
        const auto tracer = quadtreeMaker(Ascent::Parent, {0, true})(surface);
        const testing::ReferenceTracer exact(surface);
        walk_test::RayMaker maker(*surface, 9);
        for (const Ray& ray : maker.all(20)) {
            const Hit ref = exact.trace(ray), got = tracer.trace(ray);
            if (!ref.hit) continue;
            ASSERT_TRUE(got.hit) << walk_test::describe(m) << " " << walk_test::describe(ray);
            EXPECT_LE(got.t, ref.t + 1e-4f) << walk_test::describe(m);
        }
    }
}

// A registry tracer on box-surface = 2 against the texel-box reference, ray by ray.
void expectTexelBoxHits(const Tracer& tracer, const Surface& surface, uint32_t seed) {
    walk_test::RayMaker maker(surface, seed);
    const std::vector<Ray> rays = maker.all(20);
    std::vector<Hit> hits(rays.size());
    tracer.traceBatch(rays, hits);
    for (size_t k = 0; k < rays.size(); ++k) {
        const Hit ref = firstTexelBoxHit(surface, rays[k]);
        ASSERT_EQ(hits[k].hit, ref.hit) << walk_test::describe(rays[k]);
        if (ref.hit) {
            EXPECT_EQ(hits[k].t, ref.t);
        }
    }
}

// box-surface = 2, the paper's surface: the walk over the texel-box pyramid (both ascents) is
// the texel-box reference's first hit; through the registry too.
TEST(Quadtree, TexelBoxesExactOnTheirSurface) {
    for (Ascent ascent : {Ascent::Parent, Ascent::None}) {
        const auto tally = walk_test::contractOnAllMapsWith(
            [=](const std::shared_ptr<const Surface>& surface) {
                return QuadtreeTracer(
                    surface, std::make_shared<const MaxPyramid>(MaxPyramid::overTexels(*surface)),
                    ascent, {0, true});
            },
            [](const std::shared_ptr<const Surface>& s) { return walk_test::TexelBoxReference{s}; },
            ascent == Ascent::Parent ? 300 : 60, "quadtree box-surface=2 vs texel boxes");
        if (ascent == Ascent::Parent) {
            EXPECT_GE(tally.rays, 100000u);
        }
        EXPECT_EQ(tally.wrong, 0u);
    }
    const auto surface = walk_test::makeSurface({"walls", 33, 17, EdgeMode::Clamp, 0.3f});
    auto tracer = createTracer("quadtree", surface, {{"box-surface", 2.0}});
    ASSERT_TRUE(tracer.ok());
    expectTexelBoxHits(**tracer, *surface, 4);
}

// Baked with box-surface = 2 (recorded), the maps are the texel pyramid: they trace as the one
// built at load, and maps baked with and traced without it (or the other way) are refused.
TEST(Quadtree, TexelBoxesBakedMaps) {
    const TechniqueInfo& info = *findTechnique("quadtree");
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const auto surface = walk_test::makeSurface({"walls", 9, 5, edge, 0.3f});
        const ParamValues cells = *resolveParams(info, {});
        const ParamValues texels = *resolveParams(info, {{"box-surface", 2.0}});
        const auto cellMaps = info.buildMaps(TechniqueInput{surface, cells, nullptr});
        const auto texelMaps = info.buildMaps(TechniqueInput{surface, texels, nullptr});
        ASSERT_TRUE(cellMaps.ok() && texelMaps.ok());
        EXPECT_EQ(texelMaps->parameters.at("box-surface"), "2");
        EXPECT_FALSE(info.check(TechniqueInput{surface, texels, &*cellMaps}).ok());
        EXPECT_FALSE(info.check(TechniqueInput{surface, cells, &*texelMaps}).ok());
        EXPECT_FALSE(info.create(TechniqueInput{surface, cells, &*texelMaps}).ok());
        auto baked = info.create(TechniqueInput{surface, texels, &*texelMaps});
        ASSERT_TRUE(baked.ok()) << baked.error().message;
        expectTexelBoxHits(**baked, *surface, 8);
    }
}

TEST(Quadtree, EntryBelowSThroughTheWallHitsAtEntry) {
    const auto surface = walk_test::makeSurface({"flat", 40, 30, EdgeMode::Clamp, 0.5f});
    const auto tracer = quadtreeMaker(Ascent::Parent)(surface);
    const Ray ray{vec3(-5.0f, 10.0f, 2.0f), glm::normalize(vec3(1.0f, 0.1f, 0.0f)), kInfinity};
    const Hit hit = tracer.trace(ray);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.position.x, 0.0f, 1e-4f);
    EXPECT_GT(hit.steps, 0);
}

TEST(Quadtree, StepsGrowSlowlyWithSize) {
    // Straight down onto fbm: one node per level and a cell test.
    for (int size : {64, 256, 1024}) {
        const auto surface = walk_test::makeSurface({"fbm", size, size, EdgeMode::Clamp, 0.1f});
        const auto tracer = quadtreeMaker(Ascent::Parent)(surface);
        const Ray ray{vec3(0.37f * size, 0.61f * size, 0.2f * size), vec3(0, 0, -1), kInfinity};
        const Hit hit = tracer.trace(ray);
        ASSERT_TRUE(hit.hit);
        EXPECT_LE(hit.steps, tracer.pyramid().layout().levels + 1) << size;
    }
}

TEST(Quadtree, RegistryRow) {
    const TechniqueInfo* info = findTechnique("quadtree");
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->contract, Contract::Exact);
    auto tracer =
        createTracer("quadtree", walk_test::makeSurface({"fbm", 9, 5, EdgeMode::Repeat, 0.3f}),
                     {{"ascend", 0.0}, {"max-steps", 12.0}});
    EXPECT_TRUE(tracer.ok());
}

}  // namespace
}  // namespace relief
