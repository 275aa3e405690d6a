// The packet walk (quadtree's and maxmip's) against the scalar walk it vectorizes: every field of every hit
// identical, bit for bit, on adversarial maps and rays (walk_test_support.h), camera rays over
// fbm, terraces, walls and a real DEM, clamp and repeat.
#include <gtest/gtest.h>
#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

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
