// The exact row's packet walk (surface/cell_walk_packet.h) against its scalar walk: every field
// of every hit identical, bit for bit, on every Highway target this machine has, over the
// adversarial contract maps and ray families (walk_test_support.h), camera rays over fbm,
// terraces, walls and a real DEM, and shadow rays toward a light from the primary hits; clamp and
// repeat.
#include <gtest/gtest.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/camera.h>
#include <relief/surface/cell_walk_packet.h>
#include <relief/techniques/exact/exact.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace relief {
namespace {

using packet_test::forEachTarget;
using packet_test::identical;

struct Counts {
    size_t rays = 0, hits = 0, differences = 0;
};

// Scalar ray by ray; packets in 256-ray batches and odd-sized spans (a partly filled packet).
void compare(const std::shared_ptr<const Surface>& surface, const std::vector<Ray>& rays,
             const std::string& what, Counts& counts) {
    ASSERT_TRUE(packetCellWalkSupports(*surface));
    std::vector<Hit> packets(rays.size());
    const std::span<const Ray> all(rays);
    for (size_t begin = 0, k = 0; begin < rays.size(); ++k) {
        const size_t size = std::min(rays.size() - begin, k % 3 == 2 ? size_t(37) : size_t(256));
        cellsHitPackets(*surface, all.subspan(begin, size),
                        std::span<Hit>(packets).subspan(begin, size));
        begin += size;
    }
    const ExactTracer scalar(surface);
    size_t reported = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        const Hit want = scalar.trace(rays[k]);
        ++counts.rays;
        counts.hits += want.hit;
        if (identical(want, packets[k])) continue;
        ++counts.differences;
        if (reported++ < 5)
            ADD_FAILURE() << what << " " << walk_test::describe(rays[k]) << ": scalar hit "
                          << want.hit << " t " << want.t << " steps " << want.steps
                          << ", packet hit " << packets[k].hit << " t " << packets[k].t
                          << " steps " << packets[k].steps;
    }
}

std::shared_ptr<const Surface> surfaceOf(Heightfield hf, float depthRatio, EdgeMode edge) {
    const float depth = depthRatio * float(std::max(hf.width, hf.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(hf)),
                                           depth, edge);
}

// Primary rays of an orbit view, and shadow rays from their hits toward a light at 30° (as the
// cpu-peers bench makes them: from just above the hit).
void cameraAndShadowRays(const Surface& surface, float elevation, std::vector<Ray>& primary,
                         std::vector<Ray>& shadow) {
    OrbitView view;
    view.elevationDeg = elevation;
    view.azimuthDeg = 30.0f;
    primary = primaryRays(Camera(view, surface, 96, 80));
    const ExactTracer exact(std::make_shared<const Surface>(surface));
    const float light = 30.0f * std::numbers::pi_v<float> / 180.0f;
    const vec3 toLight(std::cos(light) * 0.8f, std::cos(light) * 0.6f, std::sin(light));
    shadow.clear();
    for (const Ray& ray : primary) {
        const Hit hit = exact.trace(ray);
        if (!hit.hit) continue;
        shadow.push_back(Ray{hit.position + vec3(0.0f, 0.0f, 1e-3f), toLight});
    }
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
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            std::vector<std::pair<std::string, std::shared_ptr<const Surface>>> maps;
            auto fbm = generateHeightfield("fbm", 257, 200, 3);
            ASSERT_TRUE(fbm.ok());
            maps.emplace_back("fbm 257x200", surfaceOf(std::move(*fbm), 0.1f, edge));
            auto terraces = generateHeightfield("terraces", 128, 128, 5);
            ASSERT_TRUE(terraces.ok());
            maps.emplace_back("terraces 128", surfaceOf(std::move(*terraces), 0.3f, edge));
            auto walls = generateHeightfield("walls", 96, 80, 5);
            ASSERT_TRUE(walls.ok());
            maps.emplace_back("walls 96x80", surfaceOf(std::move(*walls), 0.2f, edge));
            auto dem = loadHeightfield(std::string(RELIEF_SOURCE_DIR) +
                                       "/data/colorado-elevation-400.png");
            ASSERT_TRUE(dem.ok()) << dem.error().message;
            maps.emplace_back("colorado 400", surfaceOf(std::move(*dem), 0.1f, edge));
            for (const auto& [name, surface] : maps) {
                for (float elevation : {15.3f, 40.2f, 65.1f}) {
                    std::vector<Ray> primary, shadow;
                    cameraAndShadowRays(*surface, elevation, primary, shadow);
                    compare(surface, primary, name + " camera", counts);
                    compare(surface, shadow, name + " shadow", counts);
                }
                walk_test::RayMaker maker(*surface, 77);
                compare(surface, maker.all(300), name + " random", counts);
            }
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
            if (packets) EXPECT_TRUE(identical(scalarHits[k], want)) << walk_test::describe(rays[k]);
        }
    }
}

}  // namespace
}  // namespace relief
