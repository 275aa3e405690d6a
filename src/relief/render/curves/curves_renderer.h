#pragma once
// curves — the visibility-curve displacement renderer of Fourquet, Cowan & Mann, "Geometric
// Displacement on Plane and Sphere" (GI 2008), on the CPU, for the plane (the relief's box,
// clamp mode) and the sphere (sphere/sphere_surface.h). The registry row `curves` draws its
// images with it (TechniqueInfo::image); its stepping is shared with the row (techniques/common/curve_stepper.h).
//
// Every eye ray that can meet the relief lies in a vertical cutting plane through the eye (on the
// sphere: a plane through the eye and the centre), whose image is a line through CoP_v. Along
// each such visibility line, samples (sampling.h) are solved in order from the leading edge (or
// CoP_s) outwards by the stepping of curve_stepper.h, each starting from the previous solution; a
// pixel is the average of the shaded samples that fall in it. Lines are independent and run in
// parallel.
//
// Height field: on the plane, S of DESIGN §2 (Surface::heightAt), so that errors are measured
// against `exact`; on the sphere, R + D·h with h interpolated the same way (sphere_surface.h).
// Δs (the spacing that ε scales) is the distance between consecutive eye rays on the underlying
// surface, as in the paper; for rays past the base's silhouette (sphere) it is taken on the
// enclosing surface (top of the box / sphere of radius R + D·max h).
// Guarantee: none (contract approximate): a step can pass over a feature thinner than the gap
// between two consecutive eye rays; errors are measured per sample against the exact references.
// Departures: the leading edge is a wall of the solid (curve_stepper.h); lines are not jittered, only
// samples along them; pixels that receive no sample take the mean of their neighbours (counted).
#include <relief/core/error.h>
#include <relief/core/image.h>
#include <relief/render/curves/view_frame.h>
#include <relief/render/renderer.h>
#include <relief/sphere/sphere_surface.h>
#include <relief/techniques/common/curve_stepper.h>

#include <vector>

namespace relief::curves {

struct CurvesOptions {
    double samplesPerPixel = 2.0;
    StepParams step;
    uint64_t seed = 1;
    bool keepSamples = true;  // keep every in-image sample (for per-sample error measurement)
};

struct CurveSample {
    vec2 pixel;  // image position
    Hit hit;     // t along the eye ray through `pixel` (ViewFrame::ray); steps = evaluations
    bool inside = true;  // an inside sample (false: an extra sample past the trailing edge)
};

struct CurvesResult {
    ImageRgb8 color;
    ImageF evaluationsPerSample;  // mean evaluations of a pixel's samples; NaN without samples
    Image<Hit> hits;              // per pixel: the sample nearest to the pixel centre
    std::vector<CurveSample> samples;
    StepCounts counts;
    int64_t emptyPixels = 0;  // pixels that received no sample (filled from their neighbours)
    double seconds = 0.0;     // wall time of stepping and shading (all threads)
};

// The plane: the relief's box seen by `view`. Clamp mode only; the eye must be above the base.
Result<CurvesResult> renderCurvesPlane(const Surface& surface, const ViewFrame& view,
                                       const Shading& shading, const CurvesOptions& options);

// The sphere centred at the origin. The eye must be outside the enclosing sphere R + D·max h.
Result<CurvesResult> renderCurvesSphere(const SphereSurface& sphere, const ViewFrame& view,
                                        const Shading& shading, const CurvesOptions& options);

// The sphere per pixel through a tracer of the sphere (e.g. exact's, sphere/sphere_reference.h):
// one ray through each pixel centre, shaded like the curves samples; `samples` holds every
// pixel's ray.
CurvesResult renderSpherePixels(const SphereSurface& sphere, const ViewFrame& view,
                                const Tracer& tracer, const Shading& shading);

// Shading of a point of the displaced sphere (Lambert, colour and normal maps in texel space).
vec3 shadeSphere(const SphereSurface& sphere, const Shading& shading, const vec3& position);

}  // namespace relief::curves
