// relief view HEIGHTFIELD [technique, view, light, window options]: the interactive viewer
// (viewer/viewer.h). The technique's tracer is made by makeTracer on the GL backend, as for
// relief render --backend gl; with --mesh the material preview is built as relief render --mesh
// builds it (previewInput).
#include <relief/cli/common.h>
#include <relief/core/parallel.h>
#include <relief/preview/mesh.h>
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
    bool screenshotPanel = false;
    bool foldPanel = false;
    int threads = 0;
    bool techniqueGiven = false;
    // --mesh and the options only it reads.
    std::string mesh;
    float tiles = 0.0f;
    std::string split;
    std::vector<std::string> meshGiven;  // those of them given (set after parsing)
};

// The first row --mesh shows when -t is not given (exact, the default elsewhere, has no shader
// function).
constexpr const char* kDefaultMeshTechnique = "relaxed-cone";

// --mesh: a MeshPreview per material spec, on a surface of the spec's depth and edge mode over
// the command line's heightfield, its maps from --maps or built (as relief render --mesh).
viewer::PreviewFactory meshPreviewFactory(std::shared_ptr<const Heightfield> hf,
                                          std::string mapsPath,
                                          std::shared_ptr<const ImageRgb8> color) {
    return [hf = std::move(hf), mapsPath = std::move(mapsPath),
            color = std::move(color)](const viewer::MaterialSpec& spec)
               -> Result<preview::MeshPreview> {
        auto surface = std::make_shared<const Surface>(
            hf, spec.depth, spec.repeat ? EdgeMode::Repeat : EdgeMode::Clamp);
        const Overrides overrides(spec.params.all().begin(), spec.params.all().end());
        auto input = previewInput(*spec.technique, overrides, mapsPath, surface);
        if (!input) return input.error();
        return preview::MeshPreview::create(*spec.technique, input->params, input->maps, surface,
                                            color.get());
    };
}

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

const TechniqueInfo& viewableTechnique(const std::string& name, bool mesh) {
    const TechniqueInfo* info = findTechnique(name);
    std::string viewable;
    for (const TechniqueInfo* t : viewer::viewableTechniques(mesh))
        viewable += (viewable.empty() ? "" : ", ") + std::string(t->name);
    if (!info)
        throw CommandFailed{makeError(ErrorKind::BadArgument,
                                      "unknown technique '{}' (the "
                                      "viewer shows: {})",
                                      name, viewable)};
    if (mesh && info->shaderFunction.empty())
        throw CommandFailed{makeError(ErrorKind::Unsupported,
                                      "--mesh: {} has no shader-library function (the viewer "
                                      "shows on meshes: {})",
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
    const bool mesh = !o.mesh.empty();
    if (!mesh && !o.meshGiven.empty())
        throw CommandFailed{makeError(ErrorKind::BadArgument, "{}: read with --mesh only",
                                      o.meshGiven.front())};
    if (o.screenshotPanel && o.screenshot.empty())
        throw CommandFailed{
            {ErrorKind::BadArgument, "--screenshot-panel: read with --screenshot FILE only"}};
    if (mesh && o.overlay != "shading")
        throw CommandFailed{makeError(ErrorKind::BadArgument,
                                      "--overlay {}: not read with --mesh (it shows the shading)",
                                      o.overlay)};
    viewer::ViewerOptions v;
    v.technique = &viewableTechnique(
        mesh && !o.techniqueGiven ? std::string(kDefaultMeshTechnique) : o.technique.name, mesh);
    v.params = orFail(resolveParams(*v.technique, orFail(parameterOverrides(*v.technique, o.technique))));
    if (!o.split.empty()) v.splitTechnique = &viewableTechnique(o.split, true);
    // Before the window opens: a bad mesh exits as relief render --mesh does.
    if (mesh) v.mesh = orFail(preview::loadMesh(o.mesh));
    const auto hf = orFail(loadHeightfield(o.surface));
    v.surface = orFail(makeSurface(o.surface, hf));
    v.sourceName = o.surface.source;
    v.color = orFail(loadColorOption(o.colorPath, o.surface.source));
    v.makeTracer = glTracerFactory(v.surface, o.technique.mapsPath);
    if (mesh) {
        v.meshName = o.mesh;
        v.makePreview = meshPreviewFactory(
            hf, o.technique.mapsPath,
            v.color ? std::make_shared<const ImageRgb8>(*v.color) : nullptr);
        v.tiles = o.tiles;
    }
    v.screenshotPanel = o.screenshotPanel;
    v.panelFolded = o.foldPanel;
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
    cmd->add_option("--color", o->colorPath,
                    "colour map over the heightfield (PNG/JPEG), or gen: the generator's own");
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
    cmd->add_flag("--screenshot-panel", o->screenshotPanel, "--screenshot: with the panel over it");
    cmd->add_flag("--fold-panel", o->foldPanel, "start with the panel folded (Tab unfolds it)");
    cmd->add_option("--mesh", o->mesh,
                    "show the material on a mesh (as relief render --mesh): plane, cube, sphere, "
                    "cylinder or FILE.gltf/.glb; -t defaults to " +
                        std::string(kDefaultMeshTechnique) + " then")
        ->check([](const std::string& v) { return v.empty() ? "--mesh: empty" : ""; });
    cmd->add_option("--tiles", o->tiles,
                    "--mesh: start with tiling on (repeat edges), the map this often per uv unit")
        ->check(finiteRange(1.0, 16.0));
    cmd->add_option("--split", o->split,
                    "--mesh: start with the A/B split, this technique (its defaults) on the "
                    "right half");
    addThreadsOption(*cmd, o->threads);
    cmd->footer(
        "Mouse: drag to orbit, wheel for distance. Keys: S or F12 saves "
        "relief-view-NNN.png in the working folder, Tab folds the panel, Esc quits.");
    cmd->callback([o, cmd] {
        o->techniqueGiven = cmd->count("--technique") > 0;
        o->meshGiven.clear();
        for (const char* option : {"--tiles", "--split"})
            if (cmd->count(option) > 0) o->meshGiven.emplace_back(option);
        runView(*o);
    });
}

}  // namespace relief::cli
