// The preview shading (issue 19): sRGB round trip, mip levels that grow with the pixel's distance,
// colour maps that wrap in repeat mode (no streaks beyond the centre tile), smooth normals.
#include <relief/core/generators.h>
#include <relief/render/renderer.h>
#include <relief/render/texture.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cmath>

namespace relief {
namespace {

std::shared_ptr<const Surface> flatSurface(int w, int h, EdgeMode edge) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("flat", w, h));
    return std::make_shared<const Surface>(hf, 2.0f, edge);
}

OrbitView topView(float distance, float fov = 45.0f) {
    OrbitView view;
    view.elevationDeg = 90.0f;
    view.azimuthDeg = 30.0f;
    view.distance = distance;
    view.fovDeg = fov;
    return view;
}

// Albedo as is: full ambient, no highlight, no exposure.
Shading plainShading(ShadingModel model, const ImageRgb8* color) {
    Shading shading;
    shading.model = model;
    shading.ambient = 1.0f;
    shading.specular = 0.0f;
    shading.color = color;
    return shading;
}

RenderResult renderFlat(const Surface& surface, const OrbitView& view, const Shading& shading,
                        int size = 96) {
    auto exact = createTracer("exact", std::make_shared<const Surface>(surface));
    EXPECT_TRUE(exact);
    return render(surface, Camera(view, surface, size, size), **exact, shading);
}

TEST(PreviewTexture, SrgbRoundTripsEveryCode) {
    for (int code = 0; code < 256; ++code)
        EXPECT_EQ(encodeSrgb8(srgbToLinear(float(code) / 255.0f)), code) << code;
    EXPECT_NEAR(srgbToLinear(0.5f), 0.214f, 1e-3f);
    EXPECT_NEAR(linearToSrgb(0.214f), 0.5f, 1e-3f);
}

TEST(PreviewTexture, MipChainAveragesDownToTheMean) {
    ImageRgb8 checker(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) checker.at(x, y) = Rgb8(uint8_t((x + y) % 2 ? 255 : 0));
    const MipTexture mips(checker, false);
    ASSERT_EQ(mips.levels(), 5);  // 16×8, 8×4, 4×2, 2×1, 1×1
    EXPECT_EQ(mips.level(4).width, 1);
    EXPECT_NEAR(mips.level(1).at(2, 1).x, 0.5f, 1e-6f);
    EXPECT_NEAR(mips.sample(3.5f, 2.5f, 0.0f, EdgeMode::Clamp).x, 1.0f, 1e-6f);  // texel (3, 2)
    EXPECT_NEAR(mips.sample(3.5f, 2.5f, 9.0f, EdgeMode::Clamp).x, 0.5f, 1e-6f);
    EXPECT_EQ(mipLevel(0.5f), 0.0f);
    EXPECT_FLOAT_EQ(mipLevel(4.0f), 2.0f);
}

// Mean |albedo − 0.5| over the hit pixels of a one-texel checker seen from above: the mip level
// grows with the distance, so the checker fades to its mean (the diagnostic look aliases instead).
float checkerContrast(ShadingModel model, float distance) {
    ImageRgb8 checker(64, 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) checker.at(x, y) = Rgb8(uint8_t((x + y) % 2 ? 255 : 0));
    const auto surface = flatSurface(64, 64, EdgeMode::Clamp);
    const RenderResult r =
        renderFlat(*surface, topView(distance), plainShading(model, &checker), 64);
    double sum = 0.0;
    int n = 0;
    for (size_t k = 0; k < r.hits.pixels.size(); ++k) {
        if (!r.hits.pixels[k].hit) continue;
        const float code = float(r.color.pixels[k].x) / 255.0f;
        const float linear = model == ShadingModel::Preview ? srgbToLinear(code) : code;
        sum += std::abs(linear - 0.5f);
        ++n;
    }
    EXPECT_GT(n, 100);
    return float(sum / std::max(n, 1));
}

TEST(PreviewTexture, MipLevelGrowsWithDistance) {
    const float near = checkerContrast(ShadingModel::Preview, 0.3f);
    const float mid = checkerContrast(ShadingModel::Preview, 1.2f);
    const float far = checkerContrast(ShadingModel::Preview, 4.0f);
    EXPECT_GT(near, mid);
    EXPECT_GT(mid, far);
    EXPECT_LT(far, 0.1f);
    EXPECT_GT(near, 0.1f);  // bilinear over a one-texel checker: 0.125 on average
    EXPECT_GT(checkerContrast(ShadingModel::Diagnostic, 4.0f), 0.45f);  // nearest texels alias
}

// A sawtooth along x (one period per tile): in repeat mode every tile shows it, where a clamped
// lookup smears the edge columns into streaks beyond the centre tile.
TEST(PreviewTexture, RepeatModeWrapsTheColourMap) {
    constexpr int kW = 32;
    ImageRgb8 saw(kW, kW);
    for (int y = 0; y < kW; ++y)
        for (int x = 0; x < kW; ++x) saw.at(x, y) = Rgb8(uint8_t(8 * x), 128, 64);
    const auto surface = flatSurface(kW, kW, EdgeMode::Repeat);
    for (ShadingModel model : {ShadingModel::Diagnostic, ShadingModel::Preview}) {
        const RenderResult r = renderFlat(*surface, topView(3.0f), plainShading(model, &saw));
        int outside = 0, mismatched = 0, lo = 255, hi = 0;
        for (size_t k = 0; k < r.hits.pixels.size(); ++k) {
            const Hit& hit = r.hits.pixels[k];
            ASSERT_TRUE(hit.hit);
            if (hit.position.x < float(kW) + 1.0f || hit.position.x > 2.0f * kW - 1.0f) continue;
            ++outside;  // in the next tile along x, away from its edges
            const int got = r.color.pixels[k].x;
            lo = std::min(lo, got);
            hi = std::max(hi, got);
            // Nearest texel of the wrapped map (diagnostic); the preview filters, within its mip.
            const float u = hit.position.x - float(kW);
            const float want = model == ShadingModel::Diagnostic
                                   ? float(saw.at(int(u), 0).x)
                                   : 255.0f * linearToSrgb(srgbToLinear(8.0f * (u - 0.5f) / 255.0f));
            if (std::abs(float(got) - want) > (model == ShadingModel::Diagnostic ? 0.5f : 24.0f))
                ++mismatched;
        }
        EXPECT_GT(outside, 500);
        EXPECT_GT(hi - lo, 180) << "a streak: the next tile shows one colour";
        EXPECT_LT(mismatched, outside / 50) << int(model);
    }
}

TEST(PreviewShading, SmoothNormalsFollowTheSamples) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("ramp", 16, 8));
    const Surface ramp(hf, 15.0f, EdgeMode::Clamp);  // slope 1 texel per texel
    const vec3 n = smoothNormalAt(ramp, vec3(7.3f, 4.1f, 0.0f));
    EXPECT_NEAR(n.x, -std::sqrt(0.5f), 1e-5f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    const Surface flat(std::make_shared<const Heightfield>(*generateHeightfield("flat", 8, 8)),
                       3.0f, EdgeMode::Repeat);
    EXPECT_NEAR(smoothNormalAt(flat, vec3(-3.2f, 9.7f, 1.5f)).z, 1.0f, 1e-6f);
}

TEST(PreviewShading, DefaultRenderOfATextureIsNotDarker) {
    // The same colour map, default light: the preview's mean brightness is above the diagnostic's.
    const Heightfield bricks = *generateHeightfield("bricks", 64, 64);
    const ImageRgb8 color = *generateColorMap("bricks", 64, 64);
    const Surface surface(std::make_shared<const Heightfield>(bricks), 6.0f, EdgeMode::Clamp);
    auto mean = [&](ShadingModel model) {
        Shading shading;
        shading.model = model;
        shading.color = &color;
        const RenderResult r = renderFlat(surface, OrbitView{}, shading, 64);
        double sum = 0.0;
        for (size_t k = 0; k < r.hits.pixels.size(); ++k)
            if (r.hits.pixels[k].hit) sum += r.color.pixels[k].x + r.color.pixels[k].y;
        return sum;
    };
    EXPECT_GT(mean(ShadingModel::Preview), 1.1 * mean(ShadingModel::Diagnostic));
}

}  // namespace
}  // namespace relief
