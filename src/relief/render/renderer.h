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

RenderResult render(const Surface& surface, const Camera& camera, const Tracer& tracer,
                    const Shading& shading);

// Traces the primary rays only (no shading), in tiles, in parallel.
Image<Hit> tracePrimary(const Camera& camera, const Tracer& tracer, double* seconds = nullptr);

}  // namespace relief
