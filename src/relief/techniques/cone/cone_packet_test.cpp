// cone's packet march (cone_packet.h) against its scalar march: every field of every hit
// identical, bit for bit, on every Highway target this machine has; safe and faithful maps, the
// default cap, a small one and 8-bit codes; the adversarial contract maps and ray families
// (walk_test_support.h) and camera, shadow and random rays over fbm, terraces, walls and a real
// DEM (clamp mode: repeat keeps the scalar march).
#include <gtest/gtest.h>
#include <relief/techniques/cone/cone.h>
#include <relief/techniques/cone/cone_packet.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

#include <cstdio>

namespace relief {
namespace {

using namespace packet_test;  // rowTracer, compareRowPaths, forEachTarget, Counts, ...

const Overrides kCases[] = {{}, {{"variant", 1}}, {{"max-steps", 6}}, {{"bits", 8}}};

// f(surface, rays, what) on each adversarial contract map in clamp mode, 100 rays of each family.
template <class F>
void forEachContractMap(F f) {
    uint32_t seed = 1;
    for (const walk_test::MapSpec& m : walk_test::contractMaps()) {
        if (m.edge != EdgeMode::Clamp) continue;
        const auto surface = walk_test::makeSurface(m, seed);
        walk_test::RayMaker maker(*surface, seed++);
        f(surface, maker.all(100), walk_test::describe(m));
    }
}

// f(surface, rays, what) on each map of coherent rays: camera, shadow and random rays.
template <class F>
void forEachCoherentMap(F f) {
    for (const auto& [name, surface] : packet_test::coherentRayMaps(EdgeMode::Clamp)) {
        const auto exact = createTracer("exact", surface);
        ASSERT_TRUE(exact.ok());
        f(surface, packet_test::viewAndRandomRays(*surface, [&](const Ray& ray) {
              Hit hit;
              (*exact)->traceBatch({&ray, 1}, {&hit, 1});
              return hit;
          }),
          name);
    }
}

void report(const char* what, const Counts& counts) {
    std::printf("%s (%s): %zu rays, %zu hits, %zu differences\n", what, packetWalkTarget(),
                counts.rays, counts.hits, counts.differences);
    EXPECT_GE(counts.rays, 100000u);
    EXPECT_EQ(counts.differences, 0u);
}

TEST(ConePackets, IdenticalToScalarOnAdversarialMapsAndRays) {
    if (!packetsEnabled()) GTEST_SKIP() << "RELIEF_PACKETS=0";
    forEachTarget([] {
        Counts counts;
        forEachContractMap([&](const auto& surface, const std::vector<Ray>& rays,
                               const std::string& what) {
            for (const Overrides& overrides : kCases)
                compareRowPaths(*rowTracer("cone", surface, overrides), rays,
                                what + " " + describe(overrides), counts);
        });
        report("cone packets", counts);
    });
}

TEST(ConePackets, IdenticalToScalarOnCameraAndShadowRays) {
    if (!packetsEnabled()) GTEST_SKIP() << "RELIEF_PACKETS=0";
    forEachTarget([] {
        Counts counts;
        forEachCoherentMap([&](const auto& surface, const std::vector<Ray>& rays,
                               const std::string& what) {
            for (const Overrides& overrides : {Overrides{}, Overrides{{"variant", 1}}})
                compareRowPaths(*rowTracer("cone", surface, overrides), rays,
                                what + " " + describe(overrides), counts);
        });
        report("cone packets", counts);
    });
}

// Three packets in turn (what maps beyond 32 MiB take) against the scalar march, on the
// adversarial maps and rays and on camera and shadow rays.
TEST(ConePackets, ThreePacketsIdenticalToScalar) {
    if (!packetsEnabled()) GTEST_SKIP() << "RELIEF_PACKETS=0";
    forEachTarget([] {
        Counts counts;
        const auto compare = [&](const std::shared_ptr<const Surface>& surface,
                                 const std::vector<Ray>& rays, const std::string& what) {
            const auto tracer = rowTracer("cone", surface, {});
            const auto* packets = dynamic_cast<const PacketTracer*>(tracer.get());
            ASSERT_NE(packets, nullptr);
            const auto* scalar =
                dynamic_cast<const BatchTracer<ConeTracer>*>(&packets->scalarPath());
            ASSERT_NE(scalar, nullptr);
            const ConeTracer& cone = scalar->impl();
            compareBatches(
                [&](std::span<const Ray> span, std::span<Hit> hits) {
                    coneMarchPackets(cone.surface(), cone.map(), cone.limits(), span, hits, 3);
                },
                [&](const Ray& ray) { return cone.trace(ray); }, rays, what, counts);
        };
        forEachContractMap(compare);
        forEachCoherentMap(compare);
        report("cone, three packets", counts);
    });
}

// The row takes the packet path in clamp mode (any parameters), the scalar march in repeat mode.
TEST(ConePackets, RegistryConeTracesPacketsInClampMode) {
    for (const EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const auto surface = walk_test::makeSurface({"fbm", 64, 48, edge, 0.2f});
        const auto tracer = rowTracer("cone", surface, {});
        const bool packets = dynamic_cast<const PacketTracer*>(tracer.get()) != nullptr;
        EXPECT_EQ(packets, edge == EdgeMode::Clamp && packetsEnabled());
    }
}

}  // namespace
}  // namespace relief
