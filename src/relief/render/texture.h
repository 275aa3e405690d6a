#pragma once
// Colour and normal maps for the preview shading: linear float RGB with a box-filtered mip chain,
// sampled bilinearly and linearly between levels (trilinear), wrapped or clamped as the relief is.
#include <relief/core/image.h>
#include <relief/core/math.h>
#include <relief/surface/surface.h>

#include <vector>

namespace relief {

// The sRGB transfer functions (IEC 61966-2-1) on [0, 1].
float srgbToLinear(float encoded);
float linearToSrgb(float linear);
// Linear [0, 1] (clamped) to the nearest 8-bit sRGB code.
uint8_t encodeSrgb8(float linear);

class MipTexture {
public:
    // srgb: the codes are sRGB-encoded colours (colour maps); else linear values (normal maps).
    MipTexture(const ImageRgb8& image, bool srgb);

    int levels() const { return int(m_levels.size()); }
    const ImageRgbF& level(int k) const { return m_levels[size_t(k)]; }
    // (u, v) in level-0 texels (u along columns, v along rows, texel k centred on k + 0.5); lod
    // the fractional level (clamped to the chain), edge how texels beyond the image are found.
    vec3 sample(float u, float v, float lod, EdgeMode edge) const;

private:
    std::vector<ImageRgbF> m_levels;
};

// The bytes of a MipTexture of a width×height image (for the memory budget).
int64_t mipTextureBytes(int width, int height);

// The level whose texels are `footprint` level-0 texels wide: log2, 0 below one texel.
float mipLevel(float footprint);

}  // namespace relief
