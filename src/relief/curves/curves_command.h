#pragma once
// The `relief render` branch for the visibility-curve renderer and the sphere: the CLI parses
// and loads, this renders, measures every sample against the exact reference of its base surface
// (plane: `exact` on the same ray; sphere: sphere_reference.h) and writes the images:
// NAME.png (colour), NAME-steps.png (evaluations per sample), NAME-error.png (|t − t_ref|).
#include <relief/core/error.h>
#include <relief/curves/curves_renderer.h>
#include <relief/render/camera.h>
#include <relief/render/compare.h>

#include <memory>
#include <string>

namespace relief::curves {

enum class BaseSurface { Plane, Sphere };

struct CurvesRenderRequest {
    std::shared_ptr<const Surface> surface;  // the plane; its heightfield and depth D also
                                             // displace the sphere
    BaseSurface base = BaseSurface::Plane;
    double radius = 0.0;  // sphere radius in texels; 0: W/2π (square texels at the equator)
    std::string technique = "curves";  // "curves", or "exact" (sphere only: the reference)
    OrbitView view;
    int width = 640, height = 480;
    Shading shading;
    CurvesOptions options;
    std::string sourceName;  // for the summary
    std::string output, outDir, stepsOut, errorOut;
    bool json = false;
    bool deterministic = false;
};

struct CurvesRun {
    CurvesResult result;
    ErrorStats stats;  // per sample (plane and sphere curves) or per pixel (sphere exact)
    Image<Hit> reference;  // the reference hit of each of result.samples (curves only)
    double referenceSeconds = 0.0;
};

// Renders and measures without writing anything (tests, bench).
Result<CurvesRun> renderAndMeasure(const CurvesRenderRequest& request);

// Renders, measures, writes the images and returns the summary text (markdown or JSON).
Result<std::string> runCurvesRender(const CurvesRenderRequest& request);

}  // namespace relief::curves
