#pragma once
// The CPU renderer: primary rays by 16×16 tiles in parallel, each tile traced with one batch call
// into the technique's template instantiation, then shaded (Shading::model) with optional shadow
// rays traced by the same technique.
#include <relief/core/image.h>
#include <relief/render/camera.h>
#include <relief/techniques/technique.h>

#include <span>
#include <vector>

namespace relief {

// Diagnostic: the look the comparisons were made with (ambient + Lambert on the faceted normals,
// nearest texels, map codes and output taken as linear). Preview: a material preview (sRGB colour
// maps decoded and the output encoded, trilinear mipmapped maps with the footprint from the
// pixel's distance, a Blinn-Phong highlight, an exposure). Both wrap the maps in repeat mode.
enum class ShadingModel { Diagnostic, Preview };

struct Shading {
    vec3 towardsLight = glm::normalize(vec3(0.4f, 0.3f, 0.8f));
    float ambient = 0.25f;
    bool shadows = false;
    const ImageRgb8* color = nullptr;      // albedo over [0,W]×[0,H], row 0 at y = 0
    const ImageRgb8* normalMap = nullptr;  // tangent-space normals over [0,W]×[0,H]
    vec3 background{0.10f, 0.11f, 0.13f};  // written as is (display values) by both models
    ShadingModel model = ShadingModel::Diagnostic;
    // Preview: stops; at 0 a flat face in full light shows the colour map's own colours.
    float exposure = 0.0f;
    float specular = 0.15f;  // preview: Blinn-Phong strength
    float shininess = 40.0f;
    // Normals interpolated from per-sample normals (central differences) instead of the facets.
    bool smoothNormals = false;
};

struct RenderResult {
    Image<Hit> hits;  // primary hits, one per pixel
    ImageRgb8 color;
    double seconds = 0.0;  // wall time of tracing and shading
};

RenderResult render(const Surface& surface, const Camera& camera, const Tracer& tracer,
                    const Shading& shading);
// The peak bytes of one render() at `pixels` pixels, for the memory budget: the primary rays and
// hits while tracing, then the hits, normals, shadow rays and their hits (every pixel may need
// one) and the colour image.
int64_t renderPeakBytes(int64_t pixels, bool shadows);

// Shadow tests of `points` toward a light in direction `towardsLight` (z > 0), each ray traced
// from the light toward its point, starting above the relief's box: what a tracer that forbids
// upward rays (relaxed cones) must do, so that stopping early reads as an occluder. lit[k] = 1 when
// the first hit lies within kWrongHitDistance of the point (lifted off S as render's shadow rays
// are) or there is none.
std::vector<uint8_t> litFromTheLight(const Surface& surface, std::span<const vec3> points, const Tracer& tracer,
                                     const vec3& towardsLight);
// litFromTheLight in two halves, for timing the shadow rays alone (the bench against Embree's
// occlusion queries): the rays from the light with the length from each ray's origin to its
// lifted point, and the verdict from their hits. Each ray ends (tMax) kWrongHitDistance before
// its point: a first hit beyond that reads as lit whether it is reported or not, so the segment
// is all a tracer needs to search, the same segment Embree's occlusion query gets.
struct RaysFromTheLight {
    std::vector<Ray> rays;
    std::vector<float> lengths;
};
RaysFromTheLight raysFromTheLight(const Surface& surface, std::span<const vec3> points, const vec3& towardsLight);
std::vector<uint8_t> litFromHits(const RaysFromTheLight& light, std::span<const Hit> hits);

// Traces the primary rays only (no shading), in tiles, in parallel.
Image<Hit> tracePrimary(const Camera& camera, const Tracer& tracer, double* seconds = nullptr);

// The diagnostic shading of one point, shared with the visibility-curve renderer
// (render/curves/), which has its own hits and (on the sphere) its own tangent frames. `texel` is
// the point in texel space: x, y address the colour and normal maps, z/D tints when there is no
// colour map. Normals passed to shadeNormal are in tangent space (texel space, z up);
// shadeLambert takes world normals.
vec3 shadeAlbedo(const Surface& surface, const Shading& shading, const vec3& texel);
// The normal map's normal on top faces (tangent z > 0.5), the geometric normal elsewhere.
vec3 shadeNormal(const Surface& surface, const Shading& shading, const vec3& texel,
                 const vec3& geometricNormal);
// Ambient + Lambert; `lit` = false when the point is in shadow.
vec3 shadeLambert(const Shading& shading, const vec3& albedo, const vec3& normal, bool lit);
Rgb8 toRgb8(const vec3& linear);
// The normal interpolated bilinearly from the per-sample normals (central differences of the
// heights, wrapped or clamped by the edge mode) at (p.x, p.y).
vec3 smoothNormalAt(const Surface& surface, const vec3& p);

}  // namespace relief
