// The registry row `curves`: its per-ray tracer against the exact reference (the image renderer's
// tests are render/curves/curves_renderer_test.cpp).
#include <relief/core/generators.h>
#include <relief/render/camera.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cmath>

namespace relief {
namespace {

// The registry row's single-ray solver: walks the ray's curve; close to exact on rays from an
// orbit camera.
TEST(CurvesTracer, SingleRayWalkIsCloseToExact) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("peaks6", 64, 64, 1));
    auto surface = std::make_shared<const Surface>(hf, 6.4f, EdgeMode::Clamp);
    auto curves = createTracer("curves", surface, {{"epsilon", 0.01}});
    auto exact = createTracer("exact", surface);
    ASSERT_TRUE(curves.ok() && exact.ok());
    OrbitView view;
    view.elevationDeg = 30.0f;
    view.azimuthDeg = 20.0f;
    view.distance = 1.2f;
    const Camera camera(view, *surface, 48, 36);
    const std::vector<Ray> rays = primaryRays(camera);
    std::vector<Hit> a(rays.size()), b(rays.size());
    (*curves)->traceBatch(rays, a);
    (*exact)->traceBatch(rays, b);
    size_t wrong = 0, both = 0;
    double sum = 0.0;
    for (size_t k = 0; k < rays.size(); ++k) {
        if (a[k].hit != b[k].hit || (a[k].hit && std::abs(a[k].t - b[k].t) > 0.5f)) ++wrong;
        else if (a[k].hit) ++both, sum += std::abs(a[k].t - b[k].t);
    }
    EXPECT_GT(both, rays.size() / 5);
    EXPECT_LT(double(wrong) / double(rays.size()), 0.01);
    EXPECT_LT(sum / double(both), 0.02);
}

}  // namespace
}  // namespace relief
