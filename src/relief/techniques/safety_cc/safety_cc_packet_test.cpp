// safety-cc's packet march (safety_cc_packet.h) against its scalar march: every field of every hit
// identical, bit for bit, on every Highway target this machine has; the default maps, isotropic
// shapes (one class), positive distances, φ_max = −45° (rays outside it on the exact walk,
// counted alike) and exterior maps (how the map was built, e.g. precompute=1, does not change
// the march); the adversarial contract maps and ray families (walk_test_support.h) and camera,
// shadow and random rays over fbm, terraces, walls and a real DEM (clamp mode: repeat, a cap and
// view-dependent keep the scalar march).
#include <gtest/gtest.h>
#include <relief/techniques/registry.h>
#include <relief/techniques/safety_cc/safety_cc.h>
#include <relief/techniques/safety_cc/safety_cc_packet.h>
#include <support/packet_test_support.h>
#include <support/safety_test_support.h>
#include <support/walk_test_support.h>

#include <cstdio>

namespace relief {
namespace {

using namespace packet_test;  // rowTracer, compareRowPaths, forEachTarget, Counts, ...

const Overrides kCases[] = {{},
                            {{"isotropic", 1}},
                            {{"positive-distance", 1}},
                            {{"phi-max", -45}},
                            {{"exterior", 1}}};

TEST(SafetyCcPackets, IdenticalToScalarOnAdversarialMapsAndRays) {
    if (!packetsEnabled()) GTEST_SKIP() << "RELIEF_PACKETS=0";
    std::vector<std::pair<std::string, std::unique_ptr<Tracer>>> tracers;
    std::vector<std::vector<Ray>> rays;
    uint32_t seed = 1;
    for (const walk_test::MapSpec& m : walk_test::contractMaps()) {
        if (m.edge != EdgeMode::Clamp) continue;
        const auto surface = walk_test::makeSurface(m, seed);
        walk_test::RayMaker maker(*surface, seed++);
        rays.push_back(maker.all(100));
        for (const Overrides& overrides : kCases)
            tracers.emplace_back(walk_test::describe(m) + " " + describe(overrides),
                                 rowTracer("safety-cc", surface, overrides));
    }
    forEachTarget([&] {
        Counts counts;
        for (size_t k = 0; k < tracers.size(); ++k)
            compareRowPaths(*tracers[k].second, rays[k / std::size(kCases)], tracers[k].first,
                            counts);
        std::printf("safety-cc packets (%s): %zu rays, %zu hits, %zu differences\n",
                    packetWalkTarget(), counts.rays, counts.hits, counts.differences);
        EXPECT_GE(counts.rays, 100000u);
        EXPECT_EQ(counts.differences, 0u);
    });
}

TEST(SafetyCcPackets, IdenticalToScalarOnCameraAndShadowRays) {
    if (!packetsEnabled()) GTEST_SKIP() << "RELIEF_PACKETS=0";
    std::vector<std::pair<std::string, std::unique_ptr<Tracer>>> tracers;
    std::vector<std::vector<Ray>> rays;
    for (const auto& [name, surface] : packet_test::coherentRayMaps(EdgeMode::Clamp)) {
        const auto exact = createTracer("exact", surface);
        ASSERT_TRUE(exact.ok());
        rays.push_back(packet_test::viewAndRandomRays(*surface, [&](const Ray& ray) {
            Hit hit;
            (*exact)->traceBatch({&ray, 1}, {&hit, 1});
            return hit;
        }));
        for (const Overrides& overrides : {Overrides{}, Overrides{{"isotropic", 1}}})
            tracers.emplace_back(name + " " + describe(overrides),
                                 rowTracer("safety-cc", surface, overrides));
    }
    forEachTarget([&] {
        Counts counts;
        for (size_t k = 0; k < tracers.size(); ++k)
            compareRowPaths(*tracers[k].second, rays[k / 2], tracers[k].first, counts);
        std::printf("safety-cc packets (%s): %zu rays, %zu hits, %zu differences\n",
                    packetWalkTarget(), counts.rays, counts.hits, counts.differences);
        EXPECT_GE(counts.rays, 100000u);
        EXPECT_EQ(counts.differences, 0u);
    });
}

// The rays the march hands to the exact walk (outside φ_max) are counted by the packet path as
// by the scalar one.
TEST(SafetyCcPackets, CountsTheSameFallbacks) {
    const auto surface = walk_test::makeSurface({"fbm", 64, 48, EdgeMode::Clamp, 0.2f});
    const auto input = safety::testing::inputFor(surface, {{"phi-max", -45}}, kSafetyCcParams);
    const auto scalar = makeSafetyCcTracer(input), packets = makeSafetyCcTracer(input);
    ASSERT_TRUE(scalar && packets);
    ASSERT_TRUE(packetSafetyCcSupports(*packets));
    walk_test::RayMaker maker(*surface, 9);
    const std::vector<Ray> rays = maker.all(200);
    std::vector<Hit> hits(rays.size());
    safetyCcMarchPackets(*packets, rays, hits);
    for (const Ray& ray : rays) scalar->trace(ray);
    EXPECT_GT(scalar->fallbacks(), 0u);
    EXPECT_EQ(packets->fallbacks(), scalar->fallbacks());
}

// The row takes the packet path in clamp mode with no cap and the reference's final test, the
// scalar march otherwise.
TEST(SafetyCcPackets, RegistryTracesPacketsWhereTheyApply) {
    const struct {
        EdgeMode edge;
        Overrides overrides;
        bool packets;
    } cases[] = {{EdgeMode::Clamp, {}, true},
                 {EdgeMode::Repeat, {}, false},
                 {EdgeMode::Clamp, {{"max-steps", 8}}, false},
                 {EdgeMode::Clamp, {{"view-dependent", 1}}, false}};
    for (const auto& c : cases) {
        const auto surface = walk_test::makeSurface({"fbm", 64, 48, c.edge, 0.2f});
        const auto tracer = rowTracer("safety-cc", surface, c.overrides);
        const bool packets = dynamic_cast<const PacketTracer*>(tracer.get()) != nullptr;
        EXPECT_EQ(packets, c.packets && packetsEnabled()) << describe(c.overrides);
    }
}

}  // namespace
}  // namespace relief
