// The packet walk (quadtree's and maxmip's) against the scalar walk it vectorizes: every field of every hit
// identical, bit for bit, on adversarial maps and rays (walk_test_support.h), camera rays over
// fbm and a real DEM, clamp and repeat.
#include <gtest/gtest.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/camera.h>
#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

#include <cstdio>

namespace relief {
namespace {

using packet_test::forEachTarget;
using packet_test::identical;

struct Counts {
    size_t rays = 0, hits = 0, differences = 0;
};

// Scalar walk ray by ray; packet walk in traceAll's 256-ray batches and over odd-sized spans
// (a partly filled last packet). Both policies: Parent (quadtree), Ancestor (maxmip).
void compare(const std::shared_ptr<const Surface>& surface, const std::vector<Ray>& rays,
             const std::string& what, Counts& counts) {
    const auto pyramid = std::make_shared<const MaxPyramid>(*surface);
    ASSERT_TRUE(packetWalkSupports(*pyramid));
    for (const Ascent ascent : {Ascent::Parent, Ascent::Ancestor}) {
        std::vector<Hit> packets(rays.size());
        const std::span<const Ray> all(rays);
        for (size_t begin = 0, k = 0; begin < rays.size(); ++k) {
            const size_t size =
                std::min(rays.size() - begin, k % 3 == 2 ? size_t(37) : size_t(256));
            walkPyramidPackets(*surface, *pyramid, all.subspan(begin, size),
                               std::span<Hit>(packets).subspan(begin, size), ascent);
            begin += size;
        }
        const MaxBound bound(*pyramid);
        size_t reported = 0;
        for (size_t k = 0; k < rays.size(); ++k) {
            const Hit want =
                ascent == Ascent::Parent
                    ? walkPyramid<Ascent::Parent>(*surface, pyramid->layout(), bound, rays[k], {})
                    : walkPyramid<Ascent::Ancestor>(*surface, pyramid->layout(), bound, rays[k],
                                                    {});
            ++counts.rays;
            counts.hits += want.hit;
            if (identical(want, packets[k])) continue;
            ++counts.differences;
            if (reported++ < 5)
                ADD_FAILURE() << what << (ascent == Ascent::Parent ? " parent " : " ancestor ")
                              << walk_test::describe(rays[k]) << ": scalar hit " << want.hit
                              << " t " << want.t << " steps " << want.steps << ", packet hit "
                              << packets[k].hit << " t " << packets[k].t << " steps "
                              << packets[k].steps;
        }
    }
}

std::vector<Ray> cameraRays(const Surface& surface, float elevation, float azimuth, int width,
                            int height) {
    OrbitView view;
    view.elevationDeg = elevation;
    view.azimuthDeg = azimuth;
    return primaryRays(Camera(view, surface, width, height));
}

std::shared_ptr<const Surface> surfaceOf(Heightfield hf, float depthRatio, EdgeMode edge) {
    const float depth = depthRatio * float(std::max(hf.width, hf.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(hf)),
                                           depth, edge);
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
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            std::vector<std::pair<std::string, std::shared_ptr<const Surface>>> maps;
            auto fbm = generateHeightfield("fbm", 257, 200, 3);
            ASSERT_TRUE(fbm.ok());
            maps.emplace_back("fbm 257x200", surfaceOf(std::move(*fbm), 0.1f, edge));
            auto terraces = generateHeightfield("terraces", 128, 128, 5);
            ASSERT_TRUE(terraces.ok());
            maps.emplace_back("terraces 128", surfaceOf(std::move(*terraces), 0.3f, edge));
            auto dem = loadHeightfield(std::string(RELIEF_SOURCE_DIR) + "/data/colorado-elevation-400.png");
            ASSERT_TRUE(dem.ok()) << dem.error().message;
            maps.emplace_back("colorado 400", surfaceOf(std::move(*dem), 0.1f, edge));
            for (const auto& [name, surface] : maps) {
                for (float elevation : {15.3f, 40.2f, 65.1f})
                    compare(surface, cameraRays(*surface, elevation, 30.0f, 96, 80), name, counts);
                walk_test::RayMaker maker(*surface, 77);
                compare(surface, maker.all(300), name + " random", counts);
            }
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
