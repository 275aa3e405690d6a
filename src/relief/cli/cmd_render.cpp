// relief render HEIGHTFIELD -t TECH[,TECH...|all] [view, light, output options]
#include <relief/cli/common.h>
#include <relief/core/parallel.h>
#include <relief/curves/curves_command.h>
#include <relief/io/image_write.h>
#include <relief/render/compare.h>
#include <relief/render/renderer.h>
#include <relief/techniques/registry.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <iostream>

namespace relief::cli {

namespace {

struct RenderOptions {
    SurfaceOptions surface;
    TechniqueOptions technique;
    OrbitView view;
    std::string size = "800x600";
    float lightElevation = 45.0f;
    float lightAzimuth = 135.0f;
    std::string colorPath, normalPath;
    bool shadows = false;
    std::string output, outDir, depthOut, stepsOut, errorOut;
    std::string format = "text";
    bool deterministic = false;
    int threads = 0;
    std::string baseSurface = "plane";  // visibility curves (issue 8): plane or sphere
    double radius = 0.0;
    double epsilon = 0.05;
    double samples = 2.0;
};

struct TechniqueRun {
    std::string name;
    std::string contract;
    RenderResult result;
    ErrorStats stats;
};

std::vector<std::string> techniqueList(const std::string& spec) {
    std::vector<std::string> names;
    if (spec == "all") {
        for (const TechniqueInfo& info : techniques()) names.emplace_back(info.name);
        return names;
    }
    size_t start = 0;
    for (size_t comma; (comma = spec.find(',', start)) != std::string::npos; start = comma + 1)
        names.push_back(spec.substr(start, comma - start));
    names.push_back(spec.substr(start));
    return names;
}

Result<ivec2> parseImageSize(const std::string& text) {
    int w = 0, h = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 1 || h < 1 || w > 16384 ||
        h > 16384)
        return makeError(ErrorKind::BadArgument, "--size '{}': expected WxH, 1 to 16384 each", text);
    return ivec2(w, h);
}

void writeOutputs(const RenderOptions& o, const TechniqueRun& run, const Image<Hit>& reference,
                  const std::string& colorPath, const std::string& stepsPath,
                  const std::string& errorPath) {
    if (!colorPath.empty()) orFail(writePng(colorPath, run.result.color));
    if (!o.depthOut.empty()) orFail(writeExr(o.depthOut, depthValues(run.result.hits)));
    if (!stepsPath.empty()) orFail(writePng(stepsPath, stepsHeatmap(run.result.hits, run.stats, run.name)));
    if (!errorPath.empty())
        orFail(writePng(errorPath, errorHeatmap(run.result.hits, reference, run.stats, run.name)));
}

void printSummary(const RenderOptions& o, const std::vector<TechniqueRun>& runs, std::ostream& out) {
    if (o.format == "json") {
        nlohmann::json rows = nlohmann::json::array();
        for (const TechniqueRun& r : runs) {
            nlohmann::json row = {{"technique", r.name},        {"contract", r.contract},
                                  {"pixels", r.stats.pixels},    {"hits", r.stats.hits},
                                  {"wrong_pixels", r.stats.wrong},
                                  {"error_mean", r.stats.error.mean},
                                  {"error_p95", r.stats.error.p95},
                                  {"error_max", r.stats.error.max},
                                  {"steps_mean", r.stats.steps.mean},
                                  {"steps_max", r.stats.steps.max},
                                  {"fetches_mean", r.stats.fetches.mean}};
            if (!o.deterministic) row["seconds"] = r.result.seconds;
            rows.push_back(row);
        }
        out << rows.dump(2) << "\n";
        return;
    }
    out << "| technique | contract | mean steps | max steps | mean |err| | p95 |err| | max |err| | "
           "wrong px | ms |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const TechniqueRun& r : runs)
        out << fmt::format("| {} | {} | {:.2f} | {:.0f} | {:.3g} | {:.3g} | {:.3g} | {:.3f}% | {} |\n",
                           r.name, r.contract, r.stats.steps.mean, r.stats.steps.max,
                           r.stats.error.mean, r.stats.error.p95, r.stats.error.max,
                           100.0 * r.stats.wrongRate(),
                           o.deterministic ? std::string("-")
                                           : fmt::format("{:.1f}", 1000.0 * r.result.seconds));
}

// summary.md and summary.json beside the images, so a render folder explains itself.
void writeSummaryFiles(const RenderOptions& o, const std::vector<TechniqueRun>& runs) {
    for (const char* format : {"text", "json"}) {
        RenderOptions as = o;
        as.format = format;
        std::ostringstream text;
        if (as.format == "text")
            text << fmt::format("# relief render: {}\n\nview: elevation {} deg, azimuth {} deg, "
                                "distance {}, fov {} deg, size {}\n\n",
                                o.surface.source, o.view.elevationDeg, o.view.azimuthDeg,
                                o.view.distance, o.view.fovDeg, o.size);
        printSummary(as, runs, text);
        orFail(writeTextFile(o.outDir + (as.format == "text" ? "/summary.md" : "/summary.json"), text.str()));
    }
}

std::optional<ImageRgb8> loadOptionalImage(const std::string& path) {
    if (path.empty()) return std::nullopt;
    return orFail(loadColorImage(path));
}

// `-t curves` and `--surface sphere` go to the visibility-curve renderer (curves/curves_command.h).
void runCurvesRender(const RenderOptions& o) {
    if (o.output.empty() && o.outDir.empty())
        throw CommandFailed{{ErrorKind::BadArgument, "say where to write: -o FILE.png or --out-dir DIR"}};
    std::error_code ec;
    if (!o.outDir.empty() && (std::filesystem::create_directories(o.outDir, ec), ec))
        throw CommandFailed{makeError(ErrorKind::Io, "{}: cannot create folder: {}", o.outDir, ec.message())};
    curves::CurvesRenderRequest r;
    const ivec2 size = orFail(parseImageSize(o.size));
    r.surface = orFail(makeSurface(o.surface, orFail(loadHeightfield(o.surface))));
    r.base = o.baseSurface == "sphere" ? curves::BaseSurface::Sphere : curves::BaseSurface::Plane;
    r.radius = o.radius;
    r.technique = o.technique.name;
    r.view = o.view;
    r.width = size.x;
    r.height = size.y;
    r.shading.towardsLight = directionFromAngles(o.lightElevation, o.lightAzimuth);
    const std::optional<ImageRgb8> color = loadOptionalImage(o.colorPath);
    const std::optional<ImageRgb8> normals = loadOptionalImage(o.normalPath);
    r.shading.color = color ? &*color : nullptr;
    r.shading.normalMap = normals ? &*normals : nullptr;
    r.options.samplesPerPixel = o.samples;
    r.options.step.epsilon = o.epsilon;
    if (o.technique.maxSteps) r.options.step.maxEvaluations = *o.technique.maxSteps;
    r.sourceName = o.surface.source;
    r.output = o.output;
    r.outDir = o.outDir;
    r.stepsOut = o.stepsOut;
    r.errorOut = o.errorOut;
    r.json = o.format == "json";
    r.deterministic = o.deterministic;
    if (o.shadows) throw CommandFailed{{ErrorKind::Unsupported, "curves: --shadows is not supported"}};
    std::cout << orFail(curves::runCurvesRender(r));
}

// Techniques whose maps serve only some views (e.g. a viewing-angle restriction) say so.
void warnAboutView(const TechniqueOptions& options, const std::vector<std::string>& names,
                   const Camera& camera) {
    const std::vector<Ray> rays = primaryRays(camera);
    for (const std::string& name : names) {
        const TechniqueInfo& info = *findTechnique(name);
        if (!info.viewWarning) continue;
        const auto params = resolveParams(info, orFail(parameterOverrides(options)));
        if (!params) continue;  // makeTracer has already reported bad parameters
        const std::string warning = info.viewWarning(*params, rays);
        if (!warning.empty()) std::fprintf(stderr, "relief: warning: %s: %s\n", name.c_str(), warning.c_str());
    }
}

void runRender(const RenderOptions& o) {
    ThreadLimit limit(o.threads);
    if (o.technique.name == "curves" || o.baseSurface == "sphere") return runCurvesRender(o);
    const std::vector<std::string> names = techniqueList(o.technique.name);
    const bool many = names.size() > 1;
    if (many && o.outDir.empty())
        throw CommandFailed{{ErrorKind::BadArgument, "several techniques need --out-dir DIR"}};
    if (o.output.empty() && o.outDir.empty())
        throw CommandFailed{{ErrorKind::BadArgument, "say where to write: -o FILE.png or --out-dir DIR"}};
    if (!o.outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.outDir, ec);
        if (ec) throw CommandFailed{makeError(ErrorKind::Io, "{}: cannot create folder: {}", o.outDir, ec.message())};
    }
    const ivec2 size = orFail(parseImageSize(o.size));
    auto hf = orFail(loadHeightfield(o.surface));
    auto surface = orFail(makeSurface(o.surface, hf));
    std::vector<std::unique_ptr<Tracer>> tracers;
    for (const std::string& name : names) {
        TechniqueOptions t = o.technique;
        t.name = name;
        tracers.push_back(orFail(makeTracer(t, surface)));
    }
    const std::optional<ImageRgb8> color = loadOptionalImage(o.colorPath);
    const std::optional<ImageRgb8> normals = loadOptionalImage(o.normalPath);
    Shading shading;
    shading.towardsLight = directionFromAngles(o.lightElevation, o.lightAzimuth);
    shading.shadows = o.shadows;
    shading.color = color ? &*color : nullptr;
    shading.normalMap = normals ? &*normals : nullptr;
    const Camera camera(o.view, *surface, size.x, size.y);
    warnAboutView(o.technique, names, camera);
    auto exact = orFail(createTracer("exact", surface));
    const Image<Hit> reference = tracePrimary(camera, *exact);
    std::vector<TechniqueRun> runs;
    for (size_t k = 0; k < names.size(); ++k) {
        TechniqueRun run{names[k], std::string(toString(findTechnique(names[k])->contract)),
                         render(*surface, camera, *tracers[k], shading), {}};
        run.stats = compareHits(run.result.hits, reference);
        const std::string prefix = o.outDir.empty() ? "" : o.outDir + "/" + names[k];
        writeOutputs(o, run, reference, many || o.output.empty() ? prefix + ".png" : o.output,
                     !o.stepsOut.empty() ? o.stepsOut : (prefix.empty() ? "" : prefix + "-steps.png"),
                     !o.errorOut.empty() ? o.errorOut : (prefix.empty() ? "" : prefix + "-error.png"));
        runs.push_back(std::move(run));
    }
    printSummary(o, runs, std::cout);
    if (!o.outDir.empty()) writeSummaryFiles(o, runs);
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand(
        "render", "render a heightfield with one or several techniques (orbit camera, Lambert "
                  "shading) and compare each with the exact reference");
    addSurfaceOptions(*cmd, o->surface);
    addTechniqueOptions(*cmd, o->technique);
    cmd->get_option("--technique")->description("technique, comma-separated list, or 'all': " + techniqueNames());
    addCameraOptions(*cmd, o->view, o->lightElevation, o->lightAzimuth);
    cmd->add_option("--size", o->size, "image size WxH")->capture_default_str();
    cmd->add_option("--color", o->colorPath, "colour map over the heightfield (PNG/JPEG)");
    cmd->add_option("--normal", o->normalPath, "tangent-space normal map (PNG/JPEG)");
    cmd->add_flag("--shadows", o->shadows, "trace shadow rays with the same technique");
    cmd->add_option("-o,--output", o->output, "colour image (PNG), single technique");
    cmd->add_option("--out-dir", o->outDir, "folder for NAME.png, NAME-steps.png, NAME-error.png per technique");
    cmd->add_option("--depth-out", o->depthOut, "t per pixel as OpenEXR (single technique)");
    cmd->add_option("--steps-out", o->stepsOut, "steps heatmap PNG with colour bar (single technique)");
    cmd->add_option("--error-out", o->errorOut, "|t - t_exact| heatmap PNG (single technique)");
    cmd->add_option("--format", o->format, "summary format")->check(CLI::IsMember({"text", "json"}))->capture_default_str();
    cmd->add_flag("--deterministic", o->deterministic, "leave timings out of the summary");
    cmd->add_option("--surface", o->baseSurface, "base surface (sphere: -t curves or exact)")
        ->check(CLI::IsMember({"plane", "sphere"}))->capture_default_str();
    cmd->add_option("--radius", o->radius, "sphere radius in texels (default W/2pi)")
        ->check(CLI::Range(0.0, 1e7));
    cmd->add_option("--epsilon", o->epsilon, "curves: convergence threshold, fraction of the ray spacing")
        ->check(CLI::Range(1e-9, 10.0))->capture_default_str();
    cmd->add_option("--samples", o->samples, "curves: samples per pixel")
        ->check(CLI::Range(0.25, 256.0))->capture_default_str();
    addThreadsOption(*cmd, o->threads);
    cmd->callback([o] { runRender(*o); });
}

}  // namespace relief::cli
