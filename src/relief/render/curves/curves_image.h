#pragma once
// What `relief render` draws on the sphere and with the visibility-curve renderer, measured
// against the exact reference of the base surface (plane: the reference row on the same ray;
// sphere: sphere/sphere_reference.h). Images and summaries are written by the CLI
// (cli/cmd_render.cpp); this draws and measures only.
#include <relief/core/error.h>
#include <relief/render/camera.h>
#include <relief/render/compare.h>
#include <relief/render/curves/curves_renderer.h>
#include <relief/techniques/technique.h>

#include <memory>
#include <string_view>

namespace relief::curves {

struct CurvesScene {
    std::shared_ptr<const Surface> surface;  // the plane; its heightfield and depth also
                                             // displace the sphere
    std::shared_ptr<const SphereSurface> sphere;  // null: the plane is the base
    OrbitView view;
    int width = 640, height = 480;
    Shading shading;
};

// The surface's heightfield and depth on a sphere of `radius` texels (0: W/2π, square texels at
// the equator).
std::shared_ptr<const SphereSurface> makeSphere(const Surface& surface, double radius);

// The image renderer's options from a row's resolved parameters: `epsilon`, the parameter with
// role ImageSampling (samples per pixel) and the iteration cap (evaluations per sample).
CurvesOptions curvesOptions(const TechniqueInfo& info, const ParamValues& params);

struct CurvesRun {
    CurvesResult result;
    ErrorStats stats;  // per sample (visibility curves) or per pixel (a tracer on the sphere)
    Image<Hit> reference;  // the reference hit of each of result.samples
    double referenceSeconds = 0.0;
};

// The visibility-curve renderer on the scene's base surface, every sample measured.
Result<CurvesRun> renderAndMeasure(const CurvesScene& scene, const CurvesOptions& options);

// One ray per pixel centre on the sphere through `tracer`, measured against `reference` (null:
// the tracer is the sphere's reference and is measured against itself).
Result<CurvesRun> renderSphere(const CurvesScene& scene, const Tracer& tracer,
                               const Tracer* reference);

// Heatmaps of a run: evaluations per sample (steps per pixel), and the largest |t − t_ref| of a
// pixel's samples scaled to the 99th percentile (at least 1e-3 texel), wrong samples magenta.
ImageRgb8 stepsImage(const CurvesRun& run, std::string_view title);
ImageRgb8 errorImage(const CurvesRun& run, std::string_view title);

}  // namespace relief::curves
