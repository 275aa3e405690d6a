// relief render HEIGHTFIELD -t TECH[,TECH...|all] [view, light, output options]
// One path for every row: each is drawn with its image method (TechniqueInfo::image: per pixel
// through its tracer, or the visibility-curve renderer) on the base surface (the plane, or the
// sphere for rows that can draw it), measured against that surface's exact reference.
// With --mesh, one row's shader-library function draws the relief on a mesh through EGL instead
// (preview/mesh_renderer.h): a material preview, not a measurement.
#include <relief/cli/common.h>
#include <relief/core/memory_budget.h>
#include <relief/core/parallel.h>
#include <relief/core/progress.h>
#include <relief/io/image_write.h>
#include <relief/preview/mesh_renderer.h>
#include <relief/render/compare.h>
#include <relief/render/curves/curves_image.h>
#include <relief/render/renderer.h>
#include <relief/render/texture.h>
#include <relief/techniques/registry.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

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
    std::string shading = "preview";  // or diagnostic (Shading::model)
    float exposure = 0.0f, specular = Shading{}.specular;
    bool smoothNormals = false;
    // Which of the preview's options were given (the curves and the sphere draw the diagnostic
    // look and refuse them); set after parsing.
    std::vector<std::string> previewGiven;
    std::string output, outDir, depthOut, stepsOut, errorOut;
    std::string format = "text";
    bool deterministic = false;
    int threads = 0;
    std::string baseSurface = "plane";  // DESIGN §6: plane or sphere
    double radius = 0.0;
    // --mesh: the material preview (meshRender); which of the options only it reads were given.
    std::string mesh;
    float tiles = 1.0f;
    std::optional<float> crossingPlane;
    std::vector<std::string> meshGiven;
    // Options the mesh preview cannot honour, when given (set after parsing).
    std::vector<std::string> notForMesh;
};

// What the visibility-curve renderer adds to a run's summary (the paper's Table 1 counts).
struct CurvesSummary {
    curves::StepCounts counts;
    int64_t emptyPixels = 0;
    double samplesPerPixel = 0.0, epsilon = 0.0;
};

struct TechniqueRun {
    std::string name;
    std::string contract;
    RenderResult result;  // colour, per-pixel hits, seconds
    ErrorStats stats;     // per pixel, or per sample for the visibility curves
    // The diagnostic images, drawn only when asked for.
    std::function<ImageRgb8(const TechniqueRun&)> stepsImage, errorImage;
    std::optional<CurvesSummary> curves;
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

void writeOutputs(OutputSet& outputs, const RenderOptions& o, const TechniqueRun& run,
                  const std::string& colorPath, const std::string& stepsPath,
                  const std::string& errorPath) {
    if (!colorPath.empty()) orFail(writePng(outputs, colorPath, run.result.color));
    if (!o.depthOut.empty())
        orFail(writeFloatImage(outputs, o.depthOut, depthValues(run.result.hits)));
    if (!stepsPath.empty()) orFail(writePng(outputs, stepsPath, run.stepsImage(run)));
    if (!errorPath.empty()) orFail(writePng(outputs, errorPath, run.errorImage(run)));
}

nlohmann::json curvesJson(const CurvesSummary& c) {
    return {{"samples_per_pixel", c.samplesPerPixel}, {"epsilon", c.epsilon},
            {"visibility_curves", c.counts.curves}, {"inside_samples", c.counts.insideSamples},
            {"extra_samples", c.counts.extraSamples}, {"advance_steps", c.counts.advanceSteps},
            {"reverse_steps", c.counts.reverseSteps}, {"binary_cuts", c.counts.binaryCuts},
            {"wall_hits", c.counts.wallHits}, {"capped_samples", c.counts.cappedSamples},
            {"empty_pixels", c.emptyPixels}};
}

// The visibility-curve rows' counts, below the main table.
void printCurvesTable(const RenderOptions& o, const std::vector<TechniqueRun>& runs,
                      std::ostream& out) {
    bool any = false;
    for (const TechniqueRun& r : runs) {
        if (!r.curves) continue;
        if (!any)
            out << fmt::format(
                "\nvisibility curves: errors per sample against the {} reference on the same ray\n\n"
                "| technique | samples/px | epsilon | curves | inside | extra | advance | reverse | "
                "cuts | walls | capped | evals/sample | empty px |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
                o.baseSurface == "sphere" ? "sphere" : referenceTechnique().name);
        any = true;
        const curves::StepCounts& c = r.curves->counts;
        out << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2f} | {} "
                           "|\n",
                           r.name, r.curves->samplesPerPixel, r.curves->epsilon, c.curves,
                           c.insideSamples, c.extraSamples, c.advanceSteps, c.reverseSteps,
                           c.binaryCuts, c.wallHits, c.cappedSamples,
                           double(c.evaluations()) / double(std::max<int64_t>(1, c.samples())),
                           r.curves->emptyPixels);
    }
}

void printSummary(const RenderOptions& o, const std::vector<TechniqueRun>& runs, std::ostream& out) {
    if (o.format == "json") {
        nlohmann::json rows = nlohmann::json::array();
        for (const TechniqueRun& r : runs) {
            // Rates over the covered pixels (reference or technique hits), with the counts.
            nlohmann::json row = {{"technique", r.name},        {"contract", r.contract},
                                  {"pixels", r.stats.pixels},    {"hits", r.stats.hits},
                                  {"covered_pixels", r.stats.covered},
                                  {"both_hit_pixels", r.stats.bothHit},
                                  {"wrong_pixels", r.stats.wrong},
                                  {"wrong_rate", r.stats.coveredWrongRate()},
                                  {"error_mean", r.stats.error.mean},
                                  {"error_p95", r.stats.error.p95},
                                  {"error_max", r.stats.error.max},
                                  {"steps_mean", r.stats.coveredSteps.mean},
                                  {"steps_max", r.stats.steps.max},
                                  {"fetches_mean", r.stats.fetches.mean},
                                  {"surface", o.baseSurface}};
            if (r.curves) row.update(curvesJson(*r.curves));
            if (!o.deterministic) row["seconds"] = r.result.seconds;
            rows.push_back(row);
        }
        out << rows.dump(2) << "\n";
        return;
    }
    out << "| technique | contract | covered px | mean steps | max steps | both hit | mean |err| | "
           "p95 |err| | max |err| | wrong px | ms |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const TechniqueRun& r : runs)
        out << fmt::format("| {} | {} | {} of {} | {:.2f} | {:.0f} | {} | {:.3g} | {:.3g} | {:.3g} | "
                           "{} = {:.3f}% | {} |\n",
                           r.name, r.contract, r.stats.covered, r.stats.pixels,
                           r.stats.coveredSteps.mean, r.stats.steps.max, r.stats.bothHit,
                           r.stats.error.mean, r.stats.error.p95, r.stats.error.max, r.stats.wrong,
                           100.0 * r.stats.coveredWrongRate(),
                           o.deterministic ? std::string("-")
                                           : fmt::format("{:.1f}", 1000.0 * r.result.seconds));
    out << "\ncovered px: where the reference or the technique hits; mean steps and wrong px are "
           "over those, |err| over the pixels both hit\n";
    if (o.baseSurface == "sphere")
        out << "\non the sphere; errors against the sphere reference\n";
    printCurvesTable(o, runs, out);
}

// summary.md and summary.json beside the images, so a render folder explains itself.
void writeSummaryFiles(OutputSet& outputs, const RenderOptions& o,
                       const std::vector<TechniqueRun>& runs) {
    for (const char* format : {"text", "json"}) {
        RenderOptions as = o;
        as.format = format;
        std::ostringstream text;
        if (as.format == "text")
            text << fmt::format("# relief render: {}\n\nsurface: {}; view: elevation {} deg, "
                                "azimuth {} deg, distance {}, fov {} deg, size {}\n\n",
                                o.surface.source, o.baseSurface, o.view.elevationDeg,
                                o.view.azimuthDeg, o.view.distance, o.view.fovDeg, o.size);
        printSummary(as, runs, text);
        orFail(outputs.addText(o.outDir + (as.format == "text" ? "/summary.md" : "/summary.json"), text.str()));
    }
}

std::optional<ImageRgb8> loadOptionalImage(const std::string& path) {
    if (path.empty()) return std::nullopt;
    return orFail(loadColorImage(path));
}

// --color FILE, or `--color gen`: the generator's own colour map (bricks), at the source's size.
std::optional<ImageRgb8> loadColorMap(const RenderOptions& o) {
    if (o.colorPath != "gen") return loadOptionalImage(o.colorPath);
    if (o.surface.source.find('@') != std::string::npos)
        throw CommandFailed{makeError(ErrorKind::Unsupported,
                                      "--color gen: {}: a window of a generator has no generated "
                                      "colour map (crop the image instead)",
                                      o.surface.source)};
    return orFail(loadGeneratorColor(o.surface.source));
}

// Techniques whose maps serve only some views (e.g. a viewing-angle restriction) say so.
void warnAboutView(const TechniqueInfo& info, const ParamValues& params, const Camera& camera) {
    if (!info.viewWarning || Progress::quiet()) return;
    const std::string warning = info.viewWarning(params, primaryRays(camera));
    if (!warning.empty())
        std::fprintf(stderr, "relief: warning: %s: %s\n", std::string(info.name).c_str(),
                     warning.c_str());
}

// The rows that can be drawn on the sphere: a tracer of it, or an image method that draws it.
bool drawsSphere(const TechniqueInfo& info) {
    return info.createSphere || info.image == ImageMethod::VisibilityCurves;
}

std::string namesWhere(bool (*keep)(const TechniqueInfo&)) {
    std::string names;
    for (const TechniqueInfo& info : techniques())
        if (keep(info)) names += (names.empty() ? "" : ", ") + std::string(info.name);
    return names;
}

std::string sphereTechniqueNames() { return namesWhere(drawsSphere); }

// Everything a row's path cannot honour is refused before anything is drawn.
Status checkDrawable(const RenderOptions& o, const TechniqueInfo& info,
                     const std::vector<std::pair<std::string, double>>& overrides) {
    const bool sphere = o.baseSurface == "sphere";
    const bool curves = info.image == ImageMethod::VisibilityCurves;
    if (sphere && !drawsSphere(info))
        return makeError(ErrorKind::Unsupported,
                         "'{}' cannot trace the sphere (--surface sphere takes: {})", info.name,
                         sphereTechniqueNames());
    const std::string_view what =
        curves ? "the visibility-curve renderer" : "rendering on the sphere";
    if ((curves || sphere) && o.technique.backend != "cpu")
        return makeError(ErrorKind::Unsupported, "{}: --backend {}: {} runs on the CPU only",
                         info.name, o.technique.backend, what);
    if (curves && !sphere && o.surface.edge != "clamp")
        return makeError(ErrorKind::Unsupported, "{}: --edge {}: {} needs a finite region "
                         "(--edge clamp)", info.name, o.surface.edge, what);
    if ((curves || sphere) && o.shadows)
        return makeError(ErrorKind::Unsupported, "{}: --shadows: {} traces no shadow rays",
                         info.name, what);
    if ((curves || sphere) && !o.previewGiven.empty())
        return makeError(ErrorKind::Unsupported, "{}: {}: {} draws the diagnostic shading only",
                         info.name, o.previewGiven.front(), what);
    if (sphere && !o.technique.mapsPath.empty())
        return makeError(ErrorKind::Unsupported, "{}: --maps: baked maps are for the plane",
                         info.name);
    if (curves)
        for (const auto& [name, value] : overrides)
            for (const ParamSpec& spec : info.params)
                if (spec.name == name && spec.role == ParamRole::RayWalk)
                    return makeError(ErrorKind::BadArgument,
                                     "{}: parameter '{}' is read by the per-ray tracer only "
                                     "(relief trace); the image renderer walks whole curves",
                                     info.name, name);
    return {};
}

TechniqueRun runOf(const TechniqueInfo& info, RenderResult result, const ErrorStats& stats) {
    TechniqueRun run;
    run.name = info.name;
    run.contract = toString(info.contract);
    run.result = std::move(result);
    run.stats = stats;
    return run;
}

// A run of the curves/sphere renderer (render/curves/curves_image.h): its heatmaps are per sample.
TechniqueRun runOf(const TechniqueInfo& info, std::shared_ptr<const curves::CurvesRun> run,
                   std::string_view stepsLabel) {
    TechniqueRun out =
        runOf(info, {run->result.hits, run->result.color, run->result.seconds}, run->stats);
    out.stepsImage = [run, label = std::string(stepsLabel)](const TechniqueRun& r) {
        return curves::stepsImage(*run, r.name + " " + label);
    };
    out.errorImage = [run](const TechniqueRun& r) {
        return curves::errorImage(*run, r.name + " |t-t_ref|");
    };
    return out;
}

// The visibility-curve renderer's run, on the plane or the sphere.
TechniqueRun curvesRun(const TechniqueInfo& info, const ParamValues& params,
                       const curves::CurvesScene& scene) {
    const curves::CurvesOptions options = curves::curvesOptions(info, params);
    auto run = std::make_shared<const curves::CurvesRun>(
        orFail(curves::renderAndMeasure(scene, options)));
    TechniqueRun out = runOf(info, run, "evaluations/sample");
    out.curves = CurvesSummary{run->result.counts, run->result.emptyPixels,
                               options.samplesPerPixel, options.step.epsilon};
    return out;
}

// A row's tracer on the sphere, one ray per pixel.
TechniqueRun sphereRun(const TechniqueInfo& info, const Tracer& tracer,
                       const curves::CurvesScene& scene) {
    std::unique_ptr<Tracer> reference;
    if (!info.reference) {
        const TechniqueInfo& ref = referenceTechnique();
        reference = orFail(ref.createSphere(scene.sphere, orFail(resolveParams(ref, {}))));
    }
    return runOf(info, std::make_shared<const curves::CurvesRun>(
                           orFail(curves::renderSphere(scene, tracer, reference.get()))),
                 "steps");
}

// A per-pixel row on the plane, against the plane's reference hits.
TechniqueRun planeRun(const TechniqueInfo& info, const Surface& surface, const Camera& camera,
                      const Tracer& tracer, const Shading& shading, const Image<Hit>& reference) {
    RenderResult result = render(surface, camera, tracer, shading);
    const ErrorStats stats = compareHits(result.hits, reference);
    TechniqueRun run = runOf(info, std::move(result), stats);
    run.stepsImage = [](const TechniqueRun& r) {
        return stepsHeatmap(r.result.hits, r.stats, r.name);
    };
    run.errorImage = [&reference](const TechniqueRun& r) {
        return errorHeatmap(r.result.hits, reference, r.stats, r.name);
    };
    return run;
}

// --mesh: one row's shader-library function on a mesh (preview/mesh_renderer.h).
void meshRender(const RenderOptions& o) {
    if (!o.notForMesh.empty())
        throw CommandFailed{makeError(ErrorKind::BadArgument, "{}: not read with --mesh",
                                      o.notForMesh.front())};
    if (o.output.empty())
        throw CommandFailed{{ErrorKind::BadArgument, "--mesh: say where to write: -o FILE.png"}};
    if (o.technique.name == "all" || o.technique.name.find(',') != std::string::npos)
        throw CommandFailed{makeError(ErrorKind::BadArgument,
                                      "-t {}: --mesh draws one technique", o.technique.name)};
    const TechniqueInfo& info = *orFail(lookupTechnique(o.technique.name));
    if (info.shaderFunction.empty())
        throw CommandFailed{makeError(
            ErrorKind::Unsupported, "--mesh: {} has no shader-library function (takes: {})",
            info.name, namesWhere([](const TechniqueInfo& i) { return !i.shaderFunction.empty(); }))};
    const ivec2 size = orFail(parseImageSize(o.size));
    const preview::Mesh mesh = orFail(preview::loadMesh(o.mesh));
    const TechniqueInfo* const row[] = {&info};
    const Overrides overrides = orFail(parameterOverrides(row, o.technique)).front();
    if (!o.technique.mapsPath.empty() && !info.buildMaps)
        throw CommandFailed{makeError(ErrorKind::Unsupported, "--maps: {} reads no maps", info.name)};
    auto hf = orFail(loadHeightfield(o.surface));
    auto surface = orFail(makeSurface(o.surface, hf));
    std::shared_ptr<const MapFile> file;
    if (!o.technique.mapsPath.empty()) file = orFail(loadCheckedMaps(o.technique.mapsPath, *surface));
    const TechniqueInput input =
        orFail(techniqueInput(info, surface, overrides, file.get(), o.technique.mapsPath));
    if (info.check) orFail(info.check(input));
    TechniqueMaps built;
    if (input.maps) built = *input.maps;
    else if (info.buildMaps) built = orFail(info.buildMaps(input));
    const std::optional<ImageRgb8> color = loadColorMap(o);
    preview::MeshRenderSettings settings;
    settings.width = size.x;
    settings.height = size.y;
    settings.view = o.view;
    settings.towardsLight = directionFromAngles(o.lightElevation, o.lightAzimuth);
    settings.shadows = o.shadows;
    settings.tiles = o.tiles;
    settings.exposure = o.exposure;
    settings.specular = o.specular;
    settings.crossingHeight = o.crossingPlane;
    const preview::MeshImage image = orFail(preview::renderMesh(
        info, input.params, built, surface, mesh, color ? &*color : nullptr, settings));
    OutputSet outputs;
    orFail(writePng(outputs, o.output, image.color));
    if (!o.depthOut.empty()) orFail(writeFloatImage(outputs, o.depthOut, image.distance));
    orFail(outputs.commit());
    int64_t relief = 0, crossing = 0;
    for (preview::MeshPixel p : image.object.pixels) {
        relief += p == preview::MeshPixel::Relief;
        crossing += p == preview::MeshPixel::Crossing;
    }
    const int64_t pixels = int64_t(size.x) * size.y;
    std::ostream& out = o.output == "-" || o.depthOut == "-" ? std::cerr : std::cout;
    if (Progress::quiet()) return;
    if (o.format == "json") {
        out << nlohmann::json{{"technique", info.name}, {"mesh", o.mesh}, {"pixels", pixels},
                              {"relief_pixels", relief}, {"crossing_pixels", crossing}}
                   .dump(2)
            << "\n";
        return;
    }
    out << fmt::format("{} on mesh {}: {}x{}, relief {} px ({:.1f}%), crossing plane {} px\n",
                       info.name, o.mesh, size.x, size.y, relief, 100.0 * double(relief) / double(pixels),
                       crossing);
}

void runRender(const RenderOptions& o) {
    ThreadLimit limit(o.threads);
    if (!o.mesh.empty()) return meshRender(o);
    if (!o.meshGiven.empty())
        throw CommandFailed{makeError(ErrorKind::BadArgument, "{}: read with --mesh only",
                                      o.meshGiven.front())};
    if (o.shading == "diagnostic")
        for (const std::string& option : o.previewGiven)
            if (option != "--shading" && option != "--smooth-normals")
                throw CommandFailed{makeError(ErrorKind::BadArgument,
                                              "{}: read by --shading preview only", option)};
    std::vector<std::string> names = techniqueList(o.technique.name);
    const bool many = names.size() > 1;
    const bool sphere = o.baseSurface == "sphere";
    if (many && o.outDir.empty())
        throw CommandFailed{{ErrorKind::BadArgument, "several techniques need --out-dir DIR"}};
    if (o.output.empty() && o.outDir.empty())
        throw CommandFailed{{ErrorKind::BadArgument, "say where to write: -o FILE.png or --out-dir DIR"}};
    if (!sphere && o.radius != 0.0)
        throw CommandFailed{
            {ErrorKind::BadArgument, "--radius is the sphere's: add --surface sphere"}};
    if (sphere && o.surface.edge != "clamp")
        throw CommandFailed{{ErrorKind::Unsupported,
                             "--edge: the sphere wraps in longitude and clamps at the poles by "
                             "construction; --edge is the plane's"}};
    std::vector<const TechniqueInfo*> infos;
    for (const std::string& name : names) infos.push_back(orFail(lookupTechnique(name)));
    // Options and parameters a row lacks are left out for it (an error when no row has them).
    std::vector<Overrides> overrides = orFail(parameterOverrides(infos, o.technique));
    // `-t all` draws the rows that can honour every option and names the others; a row asked for
    // by name that cannot is an error.
    if (o.technique.name == "all") {
        for (size_t k = infos.size(); k-- > 0;) {
            const Status drawable = checkDrawable(o, *infos[k], overrides[k]);
            if (drawable || drawable.error().kind != ErrorKind::Unsupported) continue;
            if (!Progress::quiet())
                std::fprintf(stderr, "relief: note: -t all: skipping %s\n", drawable.error().message.c_str());
            infos.erase(infos.begin() + std::ptrdiff_t(k));
            overrides.erase(overrides.begin() + std::ptrdiff_t(k));
            names.erase(names.begin() + std::ptrdiff_t(k));
        }
    }
    std::vector<ParamValues> params;
    bool readsMaps = false;
    for (size_t k = 0; k < infos.size(); ++k) {
        orFail(checkDrawable(o, *infos[k], overrides[k]));
        params.push_back(orFail(resolveParams(*infos[k], overrides[k])));
        readsMaps |= infos[k]->buildMaps && infos[k]->image == ImageMethod::PerPixel;
    }
    if (!o.technique.mapsPath.empty() && !readsMaps)
        throw CommandFailed{makeError(ErrorKind::Unsupported, "--maps: {} read{} no maps",
                                      o.technique.name, many ? "" : "s")};
    const ivec2 size = orFail(parseImageSize(o.size));
    // Checked before anything is made: the reference hits, what each earlier row keeps until the
    // end (its hits and colour), and the last row's render peak (its diagnostic images, made
    // after the render's own buffers are gone, stay under it).
    const int64_t pixels = int64_t(size.x) * size.y;
    const int64_t kept = int64_t(sizeof(Hit) + sizeof(Rgb8)) * int64_t(names.size() - 1);
    orFail(reserveMemory(pixels * (int64_t(sizeof(Hit)) + kept) + renderPeakBytes(pixels, o.shadows),
                         fmt::format("render --size {}x{} with {} technique(s)", size.x, size.y,
                                     names.size())));
    if (!o.outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.outDir, ec);
        if (ec) throw CommandFailed{makeError(ErrorKind::Io, "{}: cannot create folder: {}", o.outDir, ec.message())};
    }
    auto hf = orFail(loadHeightfield(o.surface));
    auto surface = orFail(makeSurface(o.surface, hf));
    const auto sphereSurface = sphere ? curves::makeSphere(*surface, o.radius) : nullptr;
    // The per-pixel rows' tracers (maps, backend, the sphere's) before anything is drawn.
    std::vector<std::unique_ptr<Tracer>> tracers(names.size());
    std::vector<std::string> planeNames;
    for (size_t k = 0; k < names.size(); ++k) {
        if (infos[k]->image != ImageMethod::PerPixel) continue;
        if (sphere) {
            tracers[k] = orFail(infos[k]->createSphere(sphereSurface, params[k]));
            continue;
        }
        tracers[k] = orFail(makeTracer(*infos[k], overrides[k], o.technique.mapsPath,
                                       backendOf(o.technique), surface));
        planeNames.push_back(names[k]);
    }
    const std::optional<ImageRgb8> color = loadColorMap(o);
    const std::optional<ImageRgb8> normals = loadOptionalImage(o.normalPath);
    if (o.shading == "preview") {
        int64_t mips = 0;
        for (const std::optional<ImageRgb8>* map : {&color, &normals})
            if (map->has_value()) mips += mipTextureBytes((*map)->width, (*map)->height);
        orFail(reserveMemory(mips, "--shading preview: the colour and normal maps' mip levels"));
    }
    Shading shading;
    shading.towardsLight = directionFromAngles(o.lightElevation, o.lightAzimuth);
    shading.shadows = o.shadows;
    shading.color = color ? &*color : nullptr;
    shading.normalMap = normals ? &*normals : nullptr;
    // The curves and the sphere draw the diagnostic look (checkDrawable refuses the preview's
    // options for them).
    const curves::CurvesScene scene{surface, sphereSurface, o.view, size.x, size.y, shading};
    shading.model = o.shading == "preview" ? ShadingModel::Preview : ShadingModel::Diagnostic;
    shading.exposure = o.exposure;
    shading.specular = o.specular;
    shading.smoothNormals = o.smoothNormals;
    const Camera camera(o.view, *surface, size.x, size.y);
    std::optional<Image<Hit>> reference;  // the plane's, per pixel, for the per-pixel rows
    if (!planeNames.empty()) {
        for (size_t k = 0; k < infos.size(); ++k)
            if (tracers[k] && !sphere) warnAboutView(*infos[k], params[k], camera);
        auto exact = orFail(createTracer(referenceTechnique().name, surface));
        reference = tracePrimary(camera, *exact);
    }
    // Every file of the command is one transaction: none is put in place unless all were written.
    OutputSet outputs;
    std::vector<TechniqueRun> runs;
    for (size_t k = 0; k < names.size(); ++k) {
        const TechniqueInfo& info = *infos[k];
        TechniqueRun run;
        if (info.image == ImageMethod::VisibilityCurves) {
            run = curvesRun(info, params[k], scene);
        } else if (sphere) {
            run = sphereRun(info, *tracers[k], scene);
        } else {
            run = planeRun(info, *surface, camera, *tracers[k], shading, *reference);
        }
        const std::string prefix = o.outDir.empty() ? "" : o.outDir + "/" + names[k];
        writeOutputs(outputs, o, run, many || o.output.empty() ? prefix + ".png" : o.output,
                     !o.stepsOut.empty() ? o.stepsOut : (prefix.empty() ? "" : prefix + "-steps.png"),
                     !o.errorOut.empty() ? o.errorOut : (prefix.empty() ? "" : prefix + "-error.png"));
        runs.push_back(std::move(run));
    }
    if (!o.outDir.empty()) writeSummaryFiles(outputs, o, runs);
    orFail(outputs.commit());
    // An image on stdout keeps stdout to itself: the summary goes to stderr then.
    const bool imageOnStdout = o.output == "-" || o.depthOut == "-" || o.stepsOut == "-" || o.errorOut == "-";
    if (!Progress::quiet()) printSummary(o, runs, imageOnStdout ? std::cerr : std::cout);  // -q: errors only
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand(
        "render", "render a heightfield with one or several techniques (orbit camera, preview or "
                  "diagnostic shading; per pixel, or with a row's own image method: " +
                      namesWhere([](const TechniqueInfo& info) {
                          return info.image != ImageMethod::PerPixel;
                      }) +
                      ") and compare each with the exact reference of the base surface");
    addSurfaceOptions(*cmd, o->surface);
    addTechniqueOptions(*cmd, o->technique);
    cmd->get_option("--technique")->description("technique, comma-separated list, or 'all': " + techniqueNames());
    addCameraOptions(*cmd, o->view, o->lightElevation, o->lightAzimuth);
    cmd->add_option("--size", o->size, "image size WxH")->capture_default_str();
    cmd->add_option("--color", o->colorPath,
                    "colour map over the heightfield (PNG/JPEG; sRGB), or 'gen' for a generator's "
                    "own (gen:bricks:WxH)");
    cmd->add_option("--normal", o->normalPath, "tangent-space normal map (PNG/JPEG)");
    cmd->add_flag("--shadows", o->shadows, "trace shadow rays with the same technique");
    cmd->add_option("--shading", o->shading,
                    "preview: sRGB maps and output, trilinear mipmaps, highlight, exposure; "
                    "diagnostic: the comparisons' look (Lambert, nearest texels, linear codes)")
        ->check(CLI::IsMember({"preview", "diagnostic"}))->capture_default_str();
    cmd->add_option("--exposure", o->exposure, "preview: exposure in stops")
        ->check(finiteRange(-16.0, 16.0))->capture_default_str();
    cmd->add_option("--specular", o->specular, "preview: strength of the highlight")
        ->check(finiteRange(0.0, 16.0))->capture_default_str();
    cmd->add_flag("--smooth-normals", o->smoothNormals,
                  "shade with normals interpolated from per-sample normals, not the facets'");
    cmd->add_option("-o,--output", o->output, "colour image (PNG), single technique ('-' = stdout)");
    cmd->add_option("--out-dir", o->outDir, "folder for NAME.png, NAME-steps.png, NAME-error.png per technique");
    cmd->add_option(
        "--depth-out", o->depthOut,
        "t per pixel, +inf where missed (single technique): .npy (float32, shape (H,W), row 0 at "
        "the top), .pfm (grey, little endian, bottom row first) or else OpenEXR (channel Y)");
    cmd->add_option("--steps-out", o->stepsOut, "steps heatmap PNG with colour bar (single technique)");
    cmd->add_option("--error-out", o->errorOut, "|t - t_exact| heatmap PNG (single technique)");
    cmd->add_option("--format", o->format, "summary format")->check(CLI::IsMember({"text", "json"}))->capture_default_str();
    cmd->add_flag("--deterministic", o->deterministic, "leave timings out of the summary");
    cmd->add_option("--surface", o->baseSurface,
                    "base surface (sphere: " + sphereTechniqueNames() + ")")
        ->check(CLI::IsMember({"plane", "sphere"}))->capture_default_str();
    cmd->add_option("--radius", o->radius, "sphere radius in texels (default W/2pi)")
        ->check(finiteRange(0.0, 1e7));
    cmd->add_option("--mesh", o->mesh,
                    "draw the relief on a mesh with the technique's shader-library function "
                    "(GL, headless): plane, cube, sphere, cylinder or FILE.gltf/.glb; -o and "
                    "--depth-out (distance from the eye) as without it")
        ->check([](const std::string& v) { return v.empty() ? "--mesh: empty" : ""; });
    cmd->add_option("--tiles", o->tiles, "--mesh: the map repeats this often per uv unit")
        ->check(finiteRange(1e-3, 1e4))->capture_default_str();
    cmd->add_option("--crossing-plane", o->crossingPlane,
                    "--mesh: add a flat horizontal square at relief height H (0 = bottom, 1 = top "
                    "of the relief at the mesh's topmost point), to show the pixel depth offset")
        ->check(finiteRange(-16.0, 16.0));
    addThreadsOption(*cmd, o->threads);
    cmd->callback([o, cmd] {
        o->meshGiven.clear();
        for (const char* option : {"--tiles", "--crossing-plane"})
            if (cmd->count(option) > 0) o->meshGiven.emplace_back(option);
        o->notForMesh.clear();
        for (const char* option : {"--out-dir", "--steps-out", "--error-out", "--normal",
                                   "--smooth-normals", "--surface", "--radius", "--backend",
                                   "--deterministic"})
            if (cmd->count(option) > 0) o->notForMesh.emplace_back(option);
        if (o->shading != "preview") o->notForMesh.emplace_back("--shading diagnostic");
        o->previewGiven.clear();
        for (const char* option : {"--shading", "--exposure", "--specular", "--smooth-normals"})
            if (cmd->count(option) > 0 &&
                (std::string_view(option) != "--shading" || o->shading == "preview"))
                o->previewGiven.emplace_back(option);
        runRender(*o);
    });
}

}  // namespace relief::cli
