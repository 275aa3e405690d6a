// relief view HEIGHTFIELD [technique, view, light, window options]: the interactive viewer
// (viewer/viewer.h). The technique's tracer is made by makeTracer on the GL backend, as for
// relief render --backend gl.
#include <relief/cli/common.h>
#include <relief/core/parallel.h>
#include <relief/techniques/registry.h>
#include <relief/viewer/panel.h>
#include <relief/viewer/viewer.h>

namespace relief::cli {

namespace {

struct ViewOptions {
    SurfaceOptions surface;
    TechniqueOptions technique;
    std::string colorPath;
    OrbitView view;
    float lightElevation = 45.0f;
    float lightAzimuth = 135.0f;
    bool shadows = false;
    std::string overlay = "shading";
    std::vector<int> size{1024, 768};
    int frames = 0;
    std::string screenshot;
    int threads = 0;
};

// The viewer rebuilds tracers with other techniques and parameters; each goes through makeTracer
// with the panel's values as they are, so it is checked and built as on the CLI.
viewer::TracerFactory glTracerFactory(std::shared_ptr<const Surface> surface,
                                      std::string mapsPath) {
    return [surface = std::move(surface), mapsPath = std::move(mapsPath)](
               const TechniqueInfo& info, const ParamValues& params) {
        const std::vector<std::pair<std::string, double>> values(params.all().begin(),
                                                                 params.all().end());
        return makeTracer(info, values, mapsPath, Backend::Gl, surface);
    };
}

const TechniqueInfo& viewableTechnique(const std::string& name) {
    const TechniqueInfo* info = findTechnique(name);
    std::string viewable;
    for (const TechniqueInfo* t : viewer::viewableTechniques())
        viewable += (viewable.empty() ? "" : ", ") + std::string(t->name);
    if (!info)
        throw CommandFailed{makeError(ErrorKind::BadArgument,
                                      "unknown technique '{}' (the "
                                      "viewer shows: {})",
                                      name, viewable)};
    if (info->glsl.empty())
        throw CommandFailed{makeError(ErrorKind::Unsupported,
                                      "relief view traces on the GL "
                                      "backend, and '{}' has no GLSL tracer (the viewer shows: "
                                      "{})",
                                      name, viewable)};
    return *info;
}

void runView(const ViewOptions& o) {
    ThreadLimit limit(o.threads);
    viewer::ViewerOptions v;
    v.technique = &viewableTechnique(o.technique.name);
    v.params = orFail(resolveParams(*v.technique, orFail(parameterOverrides(*v.technique, o.technique))));
    v.surface = orFail(makeSurface(o.surface, orFail(loadHeightfield(o.surface))));
    v.sourceName = o.surface.source;
    if (!o.colorPath.empty()) v.color = orFail(loadColorImage(o.colorPath));
    v.makeTracer = glTracerFactory(v.surface, o.technique.mapsPath);
    v.view = o.view;
    v.lightElevationDeg = o.lightElevation;
    v.lightAzimuthDeg = o.lightAzimuth;
    v.shadows = o.shadows;
    v.overlay = o.overlay == "steps"   ? viewer::Overlay::Steps
                : o.overlay == "error" ? viewer::Overlay::Error
                                       : viewer::Overlay::Shading;
    v.windowSize = ivec2(o.size[0], o.size[1]);
    v.frames = o.frames;
    v.screenshotPath = o.screenshot;
    orFail(viewer::runViewer(v));
}

}  // namespace

void addViewCommand(CLI::App& app) {
    auto o = std::make_shared<ViewOptions>();
    CLI::App* cmd = app.add_subcommand(
        "view",
        "interactive viewer (GLFW window): orbit the relief traced on the GL backend, "
        "switch techniques and parameters, shading / steps / error overlays");
    addSurfaceOptions(*cmd, o->surface);
    addTechniqueOptions(*cmd, o->technique);
    cmd->remove_option(cmd->get_option("--backend"));  // always gl
    cmd->get_option("--technique")->description("first technique shown (one with a GLSL tracer)");
    cmd->add_option("--color", o->colorPath, "colour map over the heightfield (PNG/JPEG)");
    addCameraOptions(*cmd, o->view, o->lightElevation, o->lightAzimuth,
                     {viewer::kMinDistance, viewer::kMaxDistance, 5.0f, 120.0f});
    cmd->add_flag("--shadows", o->shadows, "trace shadow rays with the same technique");
    cmd->add_option("--overlay", o->overlay, "what the image shows")
        ->check(CLI::IsMember({"shading", "steps", "error"}))
        ->capture_default_str();
    cmd->add_option("--size", o->size, "window size WxH (default 1024x768)")
        ->delimiter('x')
        ->expected(2)
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--frames", o->frames, "draw N frames, then exit (0 = until closed)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--screenshot", o->screenshot, "PNG of the last frame, without the panel");
    addThreadsOption(*cmd, o->threads);
    cmd->footer(
        "Mouse: drag to orbit, wheel for distance. Keys: S or F12 saves "
        "relief-view-NNN.png in the working folder, Esc quits.");
    cmd->callback([o] { runView(*o); });
}

}  // namespace relief::cli
