#include <relief/render/texture.h>

#include <algorithm>
#include <cmath>

namespace relief {

float srgbToLinear(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

uint8_t encodeSrgb8(float linear) { return uint8_t(linearToSrgb(linear) * 255.0f + 0.5f); }

namespace {

// Each texel of the next level is the mean of the (up to) 2×2 texels it covers.
ImageRgbF halve(const ImageRgbF& image) {
    ImageRgbF out(std::max(1, image.width / 2), std::max(1, image.height / 2));
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const int x0 = std::min(2 * x, image.width - 1), x1 = std::min(2 * x + 1, image.width - 1);
            const int y0 = std::min(2 * y, image.height - 1), y1 = std::min(2 * y + 1, image.height - 1);
            out.at(x, y) = 0.25f * (image.at(x0, y0) + image.at(x1, y0) + image.at(x0, y1) +
                                    image.at(x1, y1));
        }
    return out;
}

vec3 bilinear(const ImageRgbF& image, float u, float v, EdgeMode edge) {
    const float fx = u - 0.5f, fy = v - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    const int x0 = int(x0f), y0 = int(y0f);
    const int xa = texelIndex(x0, image.width, edge), xb = texelIndex(x0 + 1, image.width, edge);
    const int ya = texelIndex(y0, image.height, edge), yb = texelIndex(y0 + 1, image.height, edge);
    const vec3 top = glm::mix(image.at(xa, ya), image.at(xb, ya), tx);
    const vec3 bottom = glm::mix(image.at(xa, yb), image.at(xb, yb), tx);
    return glm::mix(top, bottom, ty);
}

}  // namespace

MipTexture::MipTexture(const ImageRgb8& image, bool srgb) {
    ImageRgbF base(image.width, image.height);
    for (size_t k = 0; k < image.pixels.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const float code = float(image.pixels[k][c]) / 255.0f;
            base.pixels[k][c] = srgb ? srgbToLinear(code) : code;
        }
    m_levels.push_back(std::move(base));
    while (m_levels.back().width > 1 || m_levels.back().height > 1)
        m_levels.push_back(halve(m_levels.back()));
}

vec3 MipTexture::sample(float u, float v, float lod, EdgeMode edge) const {
    lod = std::clamp(lod, 0.0f, float(levels() - 1));
    const int k0 = int(lod), k1 = std::min(k0 + 1, levels() - 1);
    auto at = [&](int k) {
        const ImageRgbF& image = level(k);
        return bilinear(image, u * float(image.width) / float(level(0).width),
                        v * float(image.height) / float(level(0).height), edge);
    };
    const vec3 fine = at(k0);
    return k1 == k0 ? fine : glm::mix(fine, at(k1), lod - float(k0));
}

int64_t mipTextureBytes(int width, int height) {
    int64_t bytes = 0;
    for (int64_t w = width, h = height;; w = std::max<int64_t>(1, w / 2), h = std::max<int64_t>(1, h / 2)) {
        bytes += w * h * int64_t(sizeof(vec3));
        if (w == 1 && h == 1) return bytes;
    }
}

float mipLevel(float footprint) { return footprint > 1.0f ? std::log2(footprint) : 0.0f; }

}  // namespace relief
