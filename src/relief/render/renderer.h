#pragma once
// The CPU renderer: primary rays by 16×16 tiles in parallel, each tile traced with one batch call
// into the technique's template instantiation, then Lambert + ambient shading with optional
// shadow rays traced by the same technique.
#include <relief/core/image.h>
#include <relief/render/camera.h>
#include <relief/techniques/technique.h>

namespace relief {

struct Shading {
    vec3 towardsLight = glm::normalize(vec3(0.4f, 0.3f, 0.8f));
    float ambient = 0.25f;
    bool shadows = false;
    const ImageRgb8* color = nullptr;      // albedo over [0,W]×[0,H], row 0 at y = 0
    const ImageRgb8* normalMap = nullptr;  // tangent-space normals over [0,W]×[0,H]
    vec3 background{0.10f, 0.11f, 0.13f};
};

struct RenderResult {
    Image<Hit> hits;  // primary hits, one per pixel
    ImageRgb8 color;
    double seconds = 0.0;  // wall time of tracing and shading
};

// The shading pieces, shared with the visibility-curve renderer (render/curves/).
// The normal used for lighting: the normal map's where one is given and the point is on top of
// the relief, else `geometric`.
vec3 shadeNormal(const Surface& surface, const Shading& shading, const vec3& position,
                 const vec3& geometric);
vec3 shadeAlbedo(const Surface& surface, const Shading& shading, const vec3& position);
// Ambient + Lambert; `lit` false means in shadow.
vec3 shadeLambert(const Shading& shading, const vec3& albedo, const vec3& normal, bool lit);

RenderResult render(const Surface& surface, const Camera& camera, const Tracer& tracer,
                    const Shading& shading);
// The peak bytes of one render() at `pixels` pixels, for the memory budget: the primary rays and
// hits while tracing, then the hits, normals, shadow rays and their hits (every pixel may need
// one) and the colour image.
int64_t renderPeakBytes(int64_t pixels, bool shadows);

// Traces the primary rays only (no shading), in tiles, in parallel.
Image<Hit> tracePrimary(const Camera& camera, const Tracer& tracer, double* seconds = nullptr);

// The shading of one point, shared with the visibility-curve renderer (render/curves/), which has
// its own hits and (on the sphere) its own tangent frames. `texel` is the point in texel space: x, y
// address the colour and normal maps, z/D tints when there is no colour map. Normals passed to
// shadeNormal are in tangent space (texel space, z up); shadeLambert takes world normals.
vec3 shadeAlbedo(const Surface& surface, const Shading& shading, const vec3& texel);
// The normal map's normal on top faces (tangent z > 0.5), the geometric normal elsewhere.
vec3 shadeNormal(const Surface& surface, const Shading& shading, const vec3& texel,
                 const vec3& geometricNormal);
// Ambient + Lambert; `lit` = false when the point is in shadow.
vec3 shadeLambert(const Shading& shading, const vec3& albedo, const vec3& normal, bool lit);
Rgb8 toRgb8(const vec3& linear);

}  // namespace relief
