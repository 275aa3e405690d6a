#pragma once
// relief view: an interactive window over one heightfield. Rays are traced by a technique's GLSL
// tracer on the GL backend, in the window's own context (gl::EglContext::shareCurrentContext);
// the image is shaded or turned into a heatmap as relief render does it (view_renderer.h) and
// blitted to the window under a Dear ImGui panel (panel.h). Mouse: drag orbits, wheel zooms.
//
// Compiled into the relief executable only: the libraries and their tests stay free of GLFW.
#include <relief/core/error.h>
#include <relief/core/image.h>
#include <relief/preview/mesh.h>
#include <relief/render/camera.h>
#include <relief/techniques/technique.h>
#include <relief/viewer/mesh_view.h>
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
    int frames = 0;                // > 0: draw this many frames, then return
    std::string screenshotPath;    // written from the last frame (with frames > 0 or on close)
    bool screenshotPanel = false;  // ... with the panel over it
    bool panelFolded = false;      // the panel starts folded to its title bar
    // --mesh: the material preview on this mesh (mesh_view.h) instead of the traced block; the
    // technique must have a shader-library function, and so must splitTechnique (B, shown on the
    // right half from the start when given). tiles > 0: tiling on (repeat edges) from the start.
    std::optional<preview::Mesh> mesh;
    std::string meshName;
    PreviewFactory makePreview;
    const TechniqueInfo* splitTechnique = nullptr;
    float tiles = 0.0f;
};

// Opens the window and runs until it is closed (or `frames` are drawn). Errors: no display or no
// GL 4.5 context (naming what was tried), the first technique (or --mesh's A and B) failing to
// build, a screenshot that cannot be written.
Status runViewer(const ViewerOptions& options);

}  // namespace relief::viewer
