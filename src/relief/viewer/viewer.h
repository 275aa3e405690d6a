#pragma once
// relief view: an interactive window over one heightfield. Rays are traced by a technique's GLSL
// tracer on the GL backend, in the window's own context (gl::EglContext::shareCurrentContext);
// the image is shaded or turned into a heatmap as relief render does it (view_renderer.h) and
// blitted to the window under a Dear ImGui panel (panel.h). Mouse: drag orbits, wheel zooms.
//
// Compiled into the relief executable only: the libraries and their tests stay free of GLFW.
#include <relief/core/error.h>
#include <relief/core/image.h>
#include <relief/render/camera.h>
#include <relief/techniques/technique.h>
#include <relief/viewer/view_renderer.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace relief::viewer {

// Makes the GL tracer of a technique with these (complete) parameters. The CLI passes its own
// makeTracer, so maps are built, or read from --maps, exactly as for relief render --backend gl.
using TracerFactory =
    std::function<Result<std::unique_ptr<Tracer>>(const TechniqueInfo&, const ParamValues&)>;

struct ViewerOptions {
    std::shared_ptr<const Surface> surface;
    std::string sourceName;                    // the heightfield as given on the command line
    std::optional<ImageRgb8> color;            // albedo over the relief (--color)
    const TechniqueInfo* technique = nullptr;  // shown first; must have a GLSL tracer
    ParamValues params;                        // its resolved parameters
    TracerFactory makeTracer;
    OrbitView view;
    float lightElevationDeg = 45.0f;
    float lightAzimuthDeg = 135.0f;
    bool shadows = false;
    Overlay overlay = Overlay::Shading;
    ivec2 windowSize{1024, 768};
    int frames = 0;              // > 0: draw this many frames, then return
    std::string screenshotPath;  // written from the last frame (with frames > 0 or on close)
};

// Opens the window and runs until it is closed (or `frames` are drawn). Errors: no display or no
// GL 4.5 context (naming what was tried), the first technique failing to build, a screenshot
// that cannot be written.
Status runViewer(const ViewerOptions& options);

}  // namespace relief::viewer
