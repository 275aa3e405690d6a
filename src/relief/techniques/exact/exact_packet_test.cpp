// The exact row's packet walk (surface/cell_walk_packet.h) against its scalar walk: every field
// of every hit identical, bit for bit, on every Highway target this machine has, over the
// adversarial contract maps and ray families (walk_test_support.h), camera rays over fbm,
// terraces, walls and a real DEM, and shadow rays toward a light from the primary hits; clamp and
// repeat.
#include <gtest/gtest.h>
#include <relief/surface/cell_walk_packet.h>
#include <relief/techniques/exact/exact.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

#include <cstdio>

namespace relief {
namespace {

using packet_test::Counts;
using packet_test::forEachTarget;
using packet_test::identical;

// The packet walk (in batches and odd spans) against ExactTracer ray by ray.
void compare(const std::shared_ptr<const Surface>& surface, const std::vector<Ray>& rays,
             const std::string& what, Counts& counts) {
    ASSERT_TRUE(packetCellWalkSupports(*surface));
    const ExactTracer scalar(surface);
    packet_test::compareBatches(
        [&](std::span<const Ray> batch, std::span<Hit> hits) {
            cellsHitPackets(*surface, batch, hits);
        },
        [&](const Ray& ray) { return scalar.trace(ray); }, rays, what, counts);
}

TEST(ExactPackets, IdenticalToScalarOnAdversarialMapsAndRays) {
    forEachTarget([] {
        Counts counts;
        uint32_t seed = 1;
        for (const walk_test::MapSpec& m : walk_test::contractMaps()) {
            const auto surface = walk_test::makeSurface(m, seed);
            walk_test::RayMaker maker(*surface, seed++);
            compare(surface, maker.all(200), walk_test::describe(m), counts);
        }
        std::printf("exact packets (%s): %zu rays, %zu hits, %zu differences\n",
                    packetWalkTarget(), counts.rays, counts.hits, counts.differences);
        EXPECT_GE(counts.rays, 100000u);
        EXPECT_EQ(counts.differences, 0u);
    });
}

TEST(ExactPackets, IdenticalToScalarOnCameraAndShadowRays) {
    forEachTarget([] {
        Counts counts;
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (const auto& [name, surface] : packet_test::coherentRayMaps(edge)) {
                const ExactTracer exact(surface);
                for (float elevation : {15.3f, 40.2f, 65.1f}) {
                    const std::vector<Ray> primary = packet_test::cameraRays(*surface, elevation);
                    compare(surface, primary, name + " camera", counts);
                    compare(surface,
                            packet_test::shadowRays(
                                primary, [&](const Ray& ray) { return exact.trace(ray); }),
                            name + " shadow", counts);
                }
                walk_test::RayMaker maker(*surface, 77);
                compare(surface, maker.all(300), name + " random", counts);
            }
        std::printf("exact packets (%s): %zu rays, %zu hits, %zu differences\n",
                    packetWalkTarget(), counts.rays, counts.hits, counts.differences);
        EXPECT_GE(counts.rays, 100000u);
        EXPECT_EQ(counts.differences, 0u);
    });
}

// The registry's exact row takes the packet path (unless RELIEF_PACKETS=0), and its scalar path
// is the plain batch loop; both give the scalar walk's hits.
TEST(ExactPackets, RegistryExactTracesPackets) {
    for (const EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const auto surface = walk_test::makeSurface({"fbm", 64, 48, edge, 0.2f});
        walk_test::RayMaker maker(*surface, 5);
        const std::vector<Ray> rays = maker.all(100);
        auto tracer = createTracer("exact", surface);
        ASSERT_TRUE(tracer.ok());
        const auto* packets = dynamic_cast<const PacketTracer*>(tracer->get());
        EXPECT_EQ(packets != nullptr, packetsEnabled());
        const ExactTracer scalar(surface);
        std::vector<Hit> hits(rays.size()), scalarHits(rays.size());
        traceAll(**tracer, rays, hits);
        if (packets) traceAll(packets->scalarPath(), rays, scalarHits);
        for (size_t k = 0; k < rays.size(); ++k) {
            const Hit want = scalar.trace(rays[k]);
            EXPECT_TRUE(identical(hits[k], want)) << walk_test::describe(rays[k]);
            if (packets) {
                EXPECT_TRUE(identical(scalarHits[k], want)) << walk_test::describe(rays[k]);
            }
        }
    }
}

}  // namespace
}  // namespace relief
