// EmbreeScene's occlusion queries (rtcOccluded1, rtcOccluded16), the bench's shadow peers: on the
// same segments rtcOccluded1 gives rtcIntersect1's hit/miss exactly (rtcOccluded16 that of
// rtcIntersect16 and of rtcOccluded1 but on grazing rays, ≤ 0.1%), and the reference (`exact`)
// agrees with them (≤ 0.1% apart, the bench's --judge threshold), on ≥ 10^5 random and
// adversarial rays and on the cpu-peers preset's shadow rays from the light.
#include <gtest/gtest.h>
#include <relief/core/generators.h>
#include <relief/embree/embree_scene.h>
#include <relief/render/camera.h>
#include <relief/render/compare.h>
#include <relief/render/renderer.h>
#include <relief/techniques/registry.h>
#include <support/ray_sets.h>

#include <memory>
#include <string>
#include <vector>

namespace relief {
namespace {

std::shared_ptr<const Surface> surfaceOf(Heightfield hf) {
    const float depth = 0.25f * float(std::max(hf.width, hf.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(hf)),
                                           depth, EdgeMode::Clamp);
}

std::vector<std::shared_ptr<const Surface>> surfaces() {
    return {surfaceOf(*generateHeightfield("fbm", 160, 128, 3)),
            surfaceOf(*generateHeightfield("walls", 96, 96, 5))};
}

std::unique_ptr<Tracer> exactTracer(std::shared_ptr<const Surface> surface) {
    auto input = techniqueInput(referenceTechnique(), std::move(surface), {});
    EXPECT_TRUE(input) << input.error().message;
    auto tracer = referenceTechnique().create(*input);
    EXPECT_TRUE(tracer) << tracer.error().message;
    return std::move(*tracer);
}

// Each ray once unbounded and once ending at half and at twice its first hit (Embree's own):
// segments that end well before or well after the surface, never on it.
std::vector<Ray> segments(const EmbreeScene& scene, const std::vector<Ray>& rays) {
    std::vector<Hit> hits(rays.size());
    scene.intersect1(rays, hits);
    std::vector<Ray> out;
    for (size_t k = 0; k < rays.size(); ++k) {
        out.push_back(rays[k]);
        if (!hits[k].hit || !(hits[k].t > 1e-3f)) continue;
        for (float f : {0.5f, 2.0f}) {
            out.push_back(rays[k]);
            out.back().tMax = f * hits[k].t;
        }
    }
    return out;
}

TEST(EmbreeOcclusion, Occluded1And16AgreeWithIntersect1) {
    size_t total = 0;
    for (const auto& surface : surfaces()) {
        auto scene = EmbreeScene::create(*surface);
        ASSERT_TRUE(scene) << scene.error().message;
        testing::RaySets sets(*surface, 21);
        const std::vector<Ray> rays = segments(**scene, sets.all(12000));
        std::vector<Hit> hits1(rays.size()), hits16(rays.size());
        (*scene)->intersect1(rays, hits1);
        (*scene)->intersect16(rays, hits16);
        std::vector<uint8_t> one(rays.size()), sixteen(rays.size());
        (*scene)->occluded1(rays, one);
        (*scene)->occluded16(rays, sixteen);
        // Embree's single-ray and packet kernels may part on a grazing ray (about 1 in 10^4 of
        // these adversarial sets): each query agrees with its own kind exactly on all but those.
        size_t occluded = 0, vsIntersect16 = 0, vsOccluded1 = 0;
        for (size_t k = 0; k < rays.size(); ++k) {
            ASSERT_EQ(bool(one[k]), hits1[k].hit) << "ray " << k;
            vsIntersect16 += bool(sixteen[k]) != hits16[k].hit;
            vsOccluded1 += one[k] != sixteen[k];
            occluded += one[k];
        }
        EXPECT_LE(double(vsIntersect16), 1e-3 * double(rays.size()));
        EXPECT_LE(double(vsOccluded1), 1e-3 * double(rays.size()));
        // Both verdicts are common: the segments test something.
        EXPECT_GT(occluded, rays.size() / 5);
        EXPECT_LT(occluded, rays.size() - rays.size() / 10);
        total += rays.size();
    }
    EXPECT_GE(total, size_t(100000));
}

// exact's first hit within the segment against Embree's occlusion; Embree's watertight triangle
// test and exact's differ on grazing edges, hence the bench's --judge threshold (99.9%).
TEST(EmbreeOcclusion, ExactAgreesWithOcclusion) {
    for (const auto& surface : surfaces()) {
        auto scene = EmbreeScene::create(*surface);
        ASSERT_TRUE(scene) << scene.error().message;
        const std::unique_ptr<Tracer> exact = exactTracer(surface);
        testing::RaySets sets(*surface, 7);
        const std::vector<Ray> rays = segments(**scene, sets.all(12000));
        std::vector<Hit> hits(rays.size());
        traceAll(*exact, rays, hits);
        std::vector<uint8_t> occluded(rays.size());
        (*scene)->occluded16(rays, occluded);
        size_t agree = 0;
        for (size_t k = 0; k < rays.size(); ++k)
            agree += bool(occluded[k]) == (hits[k].hit && hits[k].t <= rays[k].tMax);
        EXPECT_GE(double(agree), 0.999 * double(rays.size())) << agree << " of " << rays.size();
    }
}

// The bench's shadow rays (cpu-peers): from the light down to the lit-facing primary hits of a
// view; Embree's occlusion on [0, length - kWrongHitDistance] is litFromHits' verdict on exact.
TEST(EmbreeOcclusion, ShadowRaysFromTheLightAgreeWithExact) {
    const auto surface = surfaceOf(*generateHeightfield("fbm", 128, 128, 1));
    auto scene = EmbreeScene::create(*surface);
    ASSERT_TRUE(scene) << scene.error().message;
    const std::unique_ptr<Tracer> exact = exactTracer(surface);
    const vec3 towardsLight =
        glm::normalize(vec3(std::cos(glm::radians(30.0f)), 0.0f, std::sin(glm::radians(30.0f))));
    size_t lit = 0, total = 0;
    for (float elevation : {15.3f, 40.2f, 65.1f}) {
        const Camera camera(OrbitView{elevation, 30.0f, 1.0f, 45.0f}, *surface, 160, 128);
        const Image<Hit> primary = tracePrimary(camera, *exact);
        std::vector<vec3> points;
        for (const Hit& hit : primary.pixels)
            if (hit.hit && glm::dot(surface->normalAt(hit.position), towardsLight) > 0.0f)
                points.push_back(hit.position);
        const RaysFromTheLight light = raysFromTheLight(*surface, points, towardsLight);
        std::vector<Hit> hits(light.rays.size());
        traceAll(*exact, light.rays, hits);
        const std::vector<uint8_t> exactLit = litFromHits(light, hits);
        // The rays are the segments that end kWrongHitDistance before their points; the whole
        // rays (to the floor) give the same verdicts.
        std::vector<Ray> wholeRays = light.rays;
        for (size_t k = 0; k < wholeRays.size(); ++k) {
            ASSERT_EQ(light.rays[k].tMax, std::max(0.0f, light.lengths[k] - kWrongHitDistance));
            wholeRays[k].tMax = kInfinity;
        }
        std::vector<Hit> wholeHits(wholeRays.size());
        traceAll(*exact, wholeRays, wholeHits);
        ASSERT_EQ(litFromHits(light, wholeHits), exactLit);
        const std::vector<Ray>& segmentsToPoints = light.rays;
        std::vector<uint8_t> one(points.size()), sixteen(points.size());
        (*scene)->occluded1(segmentsToPoints, one);
        (*scene)->occluded16(segmentsToPoints, sixteen);
        size_t agree = 0;
        for (size_t k = 0; k < points.size(); ++k) {
            ASSERT_EQ(one[k], sixteen[k]) << "shadow ray " << k;
            agree += bool(exactLit[k]) != bool(one[k]);
            lit += exactLit[k];
        }
        EXPECT_GE(double(agree), 0.999 * double(points.size()))
            << elevation << "°: " << agree << " of " << points.size();
        total += points.size();
    }
    EXPECT_GT(lit, total / 10);  // both lit and shadowed points
    EXPECT_LT(lit, total - total / 10);
}

}  // namespace
}  // namespace relief
