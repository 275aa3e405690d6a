// The packet walk (quadtree's and maxmip's) against the scalar walk it vectorizes: every field of every hit
// identical, bit for bit, on adversarial maps and rays (walk_test_support.h), camera rays over
// fbm, terraces, walls and a real DEM, clamp and repeat.
#include <gtest/gtest.h>
#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

#include <bit>
#include <cstdio>

namespace relief {
namespace {

using packet_test::Counts;
using packet_test::forEachTarget;
using packet_test::identical;

// The packet walk against the scalar walk it vectorizes, both policies: Parent (quadtree),
// Ancestor (maxmip).
void compare(const std::shared_ptr<const Surface>& surface, const std::vector<Ray>& rays,
             const std::string& what, Counts& counts) {
    const auto pyramid = std::make_shared<const MaxPyramid>(*surface);
    ASSERT_TRUE(packetWalkSupports(*pyramid));
    const MaxBound bound(*pyramid);
    for (const Ascent ascent : {Ascent::Parent, Ascent::Ancestor})
        packet_test::compareBatches(
            [&](std::span<const Ray> batch, std::span<Hit> hits) {
                walkPyramidPackets(*surface, *pyramid, batch, hits, ascent);
            },
            [&](const Ray& ray) {
                return ascent == Ascent::Parent
                           ? walkPyramid<Ascent::Parent>(*surface, pyramid->layout(), bound, ray, {})
                           : walkPyramid<Ascent::Ancestor>(*surface, pyramid->layout(), bound, ray,
                                                           {});
            },
            rays, what + (ascent == Ascent::Parent ? " parent" : " ancestor"), counts);
}

// startCursor's claim: below the root (the smallest node over the ray's footprint) the walk finds
// the root's hits bit for bit, in no more steps, over cells and over texel boxes; and in fewer
// (short rays: steep ones, segments such as shadow rays that end before their points).
TEST(PyramidWalk, StartBelowTheRootSameHitsNoMoreSteps) {
    size_t rays = 0, differences = 0, moreSteps = 0;
    int64_t stepsFromRoot = 0, stepsBelow = 0;
    uint32_t seed = 7;
    for (const walk_test::MapSpec& m : walk_test::contractMaps()) {
        const auto surface = walk_test::makeSurface(m, seed);
        const MaxPyramid pyramid =
            seed % 2 ? MaxPyramid(*surface) : MaxPyramid::overTexels(*surface);
        const MaxBound bound(pyramid);
        walk_test::RayMaker maker(*surface, seed++);
        std::vector<Ray> batch = maker.all(60);
        for (size_t k = 0, n = batch.size(); k < n; ++k) {  // the same rays as segments
            Ray segment = batch[k];
            const RayInterval span = surface->clip(segment);
            if (span.empty()) continue;
            segment.tMax = span.tEnter + float(k % 7 + 1) / 8.0f * (span.tExit - span.tEnter);
            batch.push_back(segment);
        }
        WalkLimits root;
        root.fromRoot = true;
        for (const Ray& ray : batch) {
            const Hit a = walkPyramid<Ascent::Parent>(*surface, pyramid.layout(), bound, ray, root);
            const Hit b = walkPyramid<Ascent::Parent>(*surface, pyramid.layout(), bound, ray, {});
            const Hit c =
                walkPyramid<Ascent::Ancestor>(*surface, pyramid.layout(), bound, ray, root);
            const Hit d = walkPyramid<Ascent::Ancestor>(*surface, pyramid.layout(), bound, ray, {});
            const auto sameHit = [](const Hit& x, const Hit& y) {
                return x.hit == y.hit &&
                       std::bit_cast<uint32_t>(x.t) == std::bit_cast<uint32_t>(y.t) &&
                       x.position == y.position;
            };
            differences += !sameHit(a, b) + !sameHit(c, d);
            moreSteps += (b.steps > a.steps) + (d.steps > c.steps);
            stepsFromRoot += a.steps + c.steps;
            stepsBelow += b.steps + d.steps;
            rays += 2;
        }
    }
    std::printf(
        "start below the root: %zu walks, %zu differences, %zu with more steps; steps %lld "
        "from the root, %lld below it\n",
        rays, differences, moreSteps, (long long)stepsFromRoot, (long long)stepsBelow);
    EXPECT_GE(rays, 100000u);
    EXPECT_EQ(differences, 0u);
    EXPECT_EQ(moreSteps, 0u);
    EXPECT_LT(stepsBelow, stepsFromRoot);
}

TEST(PyramidWalkPacket, IdenticalToScalarOnAdversarialMapsAndRays) {
    forEachTarget([] {
        Counts counts;
        uint32_t seed = 1;
        for (const walk_test::MapSpec& m : walk_test::contractMaps()) {
            const auto surface = walk_test::makeSurface(m, seed);
            walk_test::RayMaker maker(*surface, seed++);
            compare(surface, maker.all(120), walk_test::describe(m), counts);
        }
        std::printf("packet walk (%s): %zu rays, %zu hits, %zu differences\n", packetWalkTarget(),
                    counts.rays, counts.hits, counts.differences);
        EXPECT_GE(counts.rays, 100000u);
        EXPECT_EQ(counts.differences, 0u);
    });
}

TEST(PyramidWalkPacket, IdenticalToScalarOnCameraRaysFbmAndDemCrop) {
    forEachTarget([] {
        Counts counts;
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (const auto& [name, surface] : packet_test::coherentRayMaps(edge)) {
                for (float elevation : {15.3f, 40.2f, 65.1f})
                    compare(surface, packet_test::cameraRays(*surface, elevation), name, counts);
                walk_test::RayMaker maker(*surface, 77);
                compare(surface, maker.all(300), name + " random", counts);
            }
        std::printf("packet walk (%s): %zu rays, %zu hits, %zu differences\n", packetWalkTarget(),
                    counts.rays, counts.hits, counts.differences);
        EXPECT_GE(counts.rays, 100000u);
        EXPECT_EQ(counts.differences, 0u);
    });
}

// The registry's quadtree takes the packet path with its defaults only, and both give the
// scalar walk's hits.
TEST(PyramidWalkPacket, RegistryQuadtreeUsesPacketsForDefaultsOnly) {
    const auto surface = walk_test::makeSurface({"fbm", 64, 48, EdgeMode::Clamp, 0.2f});
    walk_test::RayMaker maker(*surface, 5);
    const std::vector<Ray> rays = maker.all(50);
    const QuadtreeTracer scalar(surface, std::make_shared<const MaxPyramid>(*surface),
                                Ascent::Parent, {});
    using Overrides = std::vector<std::pair<std::string, double>>;
    const Overrides cases[] = {{}, {{"ascend", 0}}, {{"max-steps", 8}}, {{"bits", 16}},
                               {{"box-surface", 1}}};
    for (const Overrides& overrides : cases) {
        const std::string what = overrides.empty() ? "defaults" : overrides[0].first;
        auto tracer = createTracer("quadtree", surface, overrides);
        ASSERT_TRUE(tracer.ok()) << what;
        const bool isScalar =
            dynamic_cast<const BatchTracer<QuadtreeTracer>*>(tracer->get()) != nullptr;
        EXPECT_EQ(isScalar, !overrides.empty() || !packetsEnabled()) << what;
        if (!overrides.empty()) continue;
        std::vector<Hit> hits(rays.size());
        traceAll(**tracer, rays, hits);
        for (size_t k = 0; k < rays.size(); ++k)
            EXPECT_TRUE(identical(hits[k], scalar.trace(rays[k]))) << walk_test::describe(rays[k]);
    }
}

}  // namespace
}  // namespace relief
