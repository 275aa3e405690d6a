#include <relief/cli/common.h>

#include <relief/core/isa.h>
#include <relief/core/memory_budget.h>
#include <relief/core/parallel.h>
#include <relief/techniques/registry.h>

#include <map>
#include <tuple>

#include <charconv>
#include <cmath>
#include <cstdio>

namespace relief::cli {

CLI::Validator finiteRange(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            double value = 0.0;
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(text.data(), end, value);
            if (ec == std::errc() && ptr == end && std::isfinite(value) && value >= lo &&
                value <= hi)
                return {};
            return fmt::format("'{}' is not a finite number from {:g} to {:g}", text, lo, hi);
        },
        fmt::format("FINITE in [{:g}, {:g}]", lo, hi));
}

void addSurfaceOptions(CLI::App& app, SurfaceOptions& o) {
    app.add_option("heightfield", o.source,
                   "height map file (PNG, JPEG, EXR, PFM, raw) or gen:NAME:WxH[:seed]; a suffix "
                   "@crop=X,Y,W,H takes the W×H window at corner X,Y (@centre=X,Y,W,H: centred on "
                   "X,Y, moved inside the map), heights renormalized to [0,1] over it")
        ->required();
    app.add_option("--depth", o.depth, "relief depth D in texels (overrides --depth-ratio)")
        ->check(finiteRange(0.0, 1e6));
    app.add_option("--depth-ratio", o.depthRatio, "relief depth as a fraction of max(W,H)")
        ->check(finiteRange(0.0, 1e6))->capture_default_str();
    app.add_option("--edge", o.edge, "edge mode")
        ->check(CLI::IsMember({"clamp", "repeat"}))
        ->capture_default_str();
    app.add_flag("--invert", o.invert, "the file is a depth map (white = deep)");
    app.add_option("--height-range", o.heightRange, "LO:HI value range of a float map");
    app.add_option("--raw", o.raw, "read a headerless file: WxH:u8|u16|f32 (little endian)");
    app.add_option("--channel", o.channel, "channel of a colour image used as height")
        ->check(CLI::IsMember({"luminance", "r", "g", "b", "a"}))
        ->capture_default_str();
    app.add_option("--max-samples", o.maxSamples, "refuse heightfields with more samples")
        ->check(CLI::Range(int64_t(1), int64_t(kMaxDimension) * kMaxDimension))
        ->capture_default_str();
    addMemoryOption(app);
}

void addMemoryOption(CLI::App& app) {
    // Sets the process-wide budget as it is parsed: nothing outlives the app (see main.cpp's -q).
    app.add_option_function<std::string>(
           "--max-memory", [](const std::string& text) { setMemoryBudget(*parseMemorySize(text)); },
           fmt::format("memory budget checked before large allocations: BYTES or NNNK/NNNM/NNNG "
                       "(default: half of physical memory, {} here)",
                       formatBytes(defaultMemoryBudget())))
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                auto parsed = parseMemorySize(text);
                return parsed ? std::string() : parsed.error().message;
            },
            "SIZE"));
}

void addTechniqueOptions(CLI::App& app, TechniqueOptions& o) {
    app.add_option("-t,--technique", o.name, "technique: " + techniqueNames())
        ->capture_default_str();
    app.add_option("--max-steps", o.maxSteps, "iteration cap of the technique");
    addRoleOptions(app, o);
    app.add_option("--param", o.params, "technique parameter NAME=VALUE (repeatable)");
    app.add_option("--maps", o.mapsPath, "baked maps (relief bake) instead of building them");
    app.add_option("--backend", o.backend, "where rays are traced")
        ->check(CLI::IsMember({"cpu", "gl"}))
        ->capture_default_str();
}

void addRoleOptions(CLI::App& app, TechniqueOptions& o) {
    app.add_option("--phi-max", o.phiMax,
                   "viewing-angle restriction of the maps in degrees (techniques that have one)");
    app.add_option("--visibility", o.visibility,
                   "rays the maps are built for: all, or exterior (viewpoint outside the box)")
        ->check(CLI::IsMember({"all", "exterior"}));
}

void addThreadsOption(CLI::App& app, int& threads) {
    app.add_option("--threads", threads, "worker threads (0 = all cores)")
        ->check(CLI::Range(0, kMaxThreads))->capture_default_str();
}

void addIsaOption(CLI::App& app) {
    // Set as it is parsed, process-wide, like --max-memory.
    app.add_option_function<std::string>(
           "--isa", [](const std::string& text) { (void)setTracerIsa(*parseIsa(text)); },
           fmt::format("instruction set of the CPU tracers: baseline, sse4, avx2 or auto (default: "
                       "RELIEF_ISA, else auto = {} here)",
                       toString(bestSupportedIsa())))
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                auto parsed = parseIsa(text);
                return parsed ? std::string() : parsed.error().message;
            },
            "ISA"));
}

void addViewOptions(CLI::App& app, OrbitView& view, const CameraLimits& limits) {
    app.add_option("--elevation", view.elevationDeg, "camera elevation above the base (degrees)")
        ->check(finiteRange(-90.0, 90.0))->capture_default_str();
    app.add_option("--azimuth", view.azimuthDeg, "camera azimuth (degrees)")
        ->check(finiteRange(-kMaxAzimuth, kMaxAzimuth))->capture_default_str();
    app.add_option("--distance", view.distance, "camera distance in box diagonals")
        ->check(finiteRange(limits.minDistance, limits.maxDistance))->capture_default_str();
    app.add_option("--fov", view.fovDeg, "vertical field of view (degrees)")
        ->check(finiteRange(limits.minFov, limits.maxFov))->capture_default_str();
}

void addCameraOptions(CLI::App& app, OrbitView& view, float& lightElevation, float& lightAzimuth,
                      const CameraLimits& limits) {
    addViewOptions(app, view, limits);
    app.add_option("--light-elevation", lightElevation, "light elevation (degrees)")
        ->check(finiteRange(-90.0, 90.0))->capture_default_str();
    app.add_option("--light-azimuth", lightAzimuth, "light azimuth (degrees)")
        ->check(finiteRange(-kMaxAzimuth, kMaxAzimuth))->capture_default_str();
}

Result<ivec2> parseImageSize(const std::string& text) {
    // from_chars: "4294967328" overflows into an error, not into 32.
    int w = 0, h = 0;
    const size_t x = text.find('x');
    const char* end = text.data() + text.size();
    const auto a = std::from_chars(text.data(), text.data() + std::min(x, text.size()), w);
    const auto b = x == std::string::npos ? a : std::from_chars(text.data() + x + 1, end, h);
    const bool parsed = x != std::string::npos && a.ec == std::errc() && a.ptr == text.data() + x &&
                        b.ec == std::errc() && b.ptr == end;
    if (!parsed || w < 1 || h < 1 || w > 16384 || h > 16384)
        return makeError(ErrorKind::BadArgument, "--size '{}': expected WxH, 1 to 16384 each",
                         text);
    return ivec2(w, h);
}

namespace {

Result<Overrides> namedParams(const TechniqueOptions& o) {
    Overrides overrides;
    for (const std::string& p : o.params) {
        auto list = parseParamList(p);
        if (!list || list->size() != 1)
            return makeError(ErrorKind::BadArgument, "--param '{}': expected NAME=NUMBER", p);
        overrides.push_back(list->front());
    }
    return overrides;
}

// The role options that were given, with the value each sets.
std::vector<std::tuple<ParamRole, const char*, double>> roleValues(const TechniqueOptions& o) {
    std::vector<std::tuple<ParamRole, const char*, double>> values;
    if (o.maxSteps) values.emplace_back(ParamRole::IterationCap, "--max-steps", double(*o.maxSteps));
    if (o.phiMax) values.emplace_back(ParamRole::PhiMax, "--phi-max", *o.phiMax);
    if (!o.visibility.empty())
        values.emplace_back(ParamRole::Visibility, "--visibility", o.visibility == "exterior" ? 1.0 : 0.0);
    return values;
}

bool hasParam(const TechniqueInfo& info, std::string_view name) {
    for (const ParamSpec& p : info.params)
        if (p.name == name) return true;
    return false;
}

std::string namesOf(std::span<const TechniqueInfo* const> infos) {
    std::string names;
    for (const TechniqueInfo* info : infos) names += (names.empty() ? "" : ", ") + std::string(info->name);
    return names;
}

}  // namespace

Backend backendOf(const TechniqueOptions& o) { return o.backend == "gl" ? Backend::Gl : Backend::Cpu; }

Result<std::vector<Overrides>> parameterOverrides(std::span<const TechniqueInfo* const> infos,
                                                  const TechniqueOptions& o) {
    auto named = namedParams(o);
    if (!named) return named.error();
    std::vector<Overrides> result(infos.size());
    for (const auto& [role, option, value] : roleValues(o)) {
        bool used = false;
        for (size_t k = 0; k < infos.size(); ++k)
            if (const ParamSpec* spec = paramWithRole(*infos[k], role)) {
                result[k].emplace_back(std::string(spec->name), value);
                used = true;
            }
        if (!used)
            return makeError(ErrorKind::BadArgument, "{}: {} {} parameter", option,
                             infos.size() == 1
                                 ? fmt::format("technique '{}' has no", infos[0]->name)
                                 : fmt::format("none of {} has a", namesOf(infos)),
                             toString(role));
    }
    for (const auto& [name, value] : *named) {
        bool used = false;
        for (size_t k = 0; k < infos.size(); ++k)
            if (hasParam(*infos[k], name)) {
                result[k].emplace_back(name, value);
                used = true;
            }
        if (!used && infos.size() > 1)
            return makeError(ErrorKind::BadArgument, "--param {}: none of {} has this parameter",
                             name, namesOf(infos));
        if (!used) result[0].emplace_back(name, value);  // resolveParams names the technique
    }
    // Twice the same parameter (two --param, or --param and its role option): the last would win
    // silently.
    for (size_t k = 0; k < infos.size(); ++k)
        for (size_t a = 0; a < result[k].size(); ++a)
            for (size_t b = a + 1; b < result[k].size(); ++b)
                if (result[k][a].first == result[k][b].first)
                    return makeError(ErrorKind::BadArgument,
                                     "{}: parameter '{}' is given twice "
                                     "(by --param or by the option of its role)",
                                     infos[k]->name, result[k][a].first);
    return result;
}

Result<Overrides> parameterOverrides(const TechniqueInfo& info, const TechniqueOptions& o) {
    const TechniqueInfo* infos[] = {&info};
    auto result = parameterOverrides(infos, o);
    if (!result) return result.error();
    return std::move(result->front());
}


Result<std::unique_ptr<Tracer>> makeTracer(const TechniqueOptions& o,
                                           std::shared_ptr<const Surface> surface) {
    auto info = lookupTechnique(o.name);
    if (!info) return info.error();
    auto overrides = parameterOverrides(**info, o);
    if (!overrides) return overrides.error();
    // Never accepted unread: the file would not even be opened.
    if (!o.mapsPath.empty() && !(*info)->buildMaps)
        return makeError(ErrorKind::Unsupported, "--maps: {} reads no maps", (*info)->name);
    return makeTracer(**info, *overrides, o.mapsPath,
                      backendOf(o), std::move(surface));
}

Result<std::unique_ptr<Tracer>> makeTracer(
    const TechniqueInfo& info, const std::vector<std::pair<std::string, double>>& overrides,
    const std::string& mapsPath, Backend backend, std::shared_ptr<const Surface> surface) {
    std::shared_ptr<const MapFile> maps;
    if (!mapsPath.empty() && info.buildMaps) {
        auto loaded = loadCheckedMaps(mapsPath, *surface);
        if (!loaded) return loaded.error();
        maps = *loaded;  // the cache in loadCheckedMaps outlives every tracer
    }
    auto input = techniqueInput(info, std::move(surface), overrides, maps.get(), mapsPath);
    if (!input) return input.error();
    return createTracer(backend, info, *input);
}

Result<std::optional<ImageRgb8>> loadColorOption(const std::string& path,
                                                 const std::string& source) {
    if (path.empty()) return std::optional<ImageRgb8>();
    if (path != "gen") {
        auto image = loadColorImage(path);
        if (!image) return image.error();
        return std::optional<ImageRgb8>(std::move(*image));
    }
    if (source.find('@') != std::string::npos)
        return makeError(ErrorKind::Unsupported,
                         "--color gen: {}: a window of a generator has no generated colour map "
                         "(crop the image instead)",
                         source);
    auto image = loadGeneratorColor(source);
    if (!image) return image.error();
    return std::optional<ImageRgb8>(std::move(*image));
}

Result<PreviewInput> previewInput(const TechniqueInfo& info, const Overrides& overrides,
                                  const std::string& mapsPath,
                                  std::shared_ptr<const Surface> surface) {
    if (!mapsPath.empty() && !info.buildMaps)
        return makeError(ErrorKind::Unsupported, "--maps: {} reads no maps", info.name);
    std::shared_ptr<const MapFile> file;
    if (!mapsPath.empty()) {
        auto loaded = loadCheckedMaps(mapsPath, *surface);
        if (!loaded) return loaded.error();
        file = *loaded;  // cached by loadCheckedMaps
    }
    auto input = techniqueInput(info, std::move(surface), overrides, file.get(), mapsPath);
    if (!input) return input.error();
    if (info.check)
        if (Status s = info.check(*input); !s) return s.error();
    PreviewInput out{input->params, {}};
    if (input->maps) {
        out.maps = *input->maps;
    } else if (info.buildMaps) {
        auto built = info.buildMaps(*input);
        if (!built) return built.error();
        out.maps = std::move(*built);
    }
    return out;
}

int report(const Error& error) {
    std::fprintf(stderr, "relief: error: %s\n", error.message.c_str());
    return int(error.kind);
}

}  // namespace relief::cli
