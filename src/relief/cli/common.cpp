#include <relief/cli/common.h>

#include <relief/core/parallel.h>
#include <relief/techniques/registry.h>

#include <charconv>
#include <cmath>
#include <cstdio>

namespace relief::cli {

void addSurfaceOptions(CLI::App& app, SurfaceOptions& o) {
    app.add_option("heightfield", o.source,
                   "height map file (PNG, JPEG, EXR, PFM, raw) or gen:NAME:WxH[:seed]")
        ->required();
    app.add_option("--depth", o.depth, "relief depth D in texels (overrides --depth-ratio)");
    app.add_option("--depth-ratio", o.depthRatio, "relief depth as a fraction of max(W,H)")
        ->capture_default_str();
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
        ->capture_default_str();
}

void addTechniqueOptions(CLI::App& app, TechniqueOptions& o) {
    app.add_option("-t,--technique", o.name, "technique: " + techniqueNames())
        ->capture_default_str();
    app.add_option("--max-steps", o.maxSteps, "iteration cap of the technique");
    app.add_option("--param", o.params, "technique parameter NAME=VALUE (repeatable)");
    app.add_option("--maps", o.mapsPath, "baked maps (relief bake) instead of building them");
    app.add_option("--backend", o.backend, "where rays are traced")
        ->check(CLI::IsMember({"cpu", "gl"}))
        ->capture_default_str();
}

void addThreadsOption(CLI::App& app, int& threads) {
    app.add_option("--threads", threads, "worker threads (0 = all cores)")->capture_default_str();
}

void addCameraOptions(CLI::App& app, OrbitView& view, float& lightElevation, float& lightAzimuth,
                      const CameraLimits& limits) {
    app.add_option("--elevation", view.elevationDeg, "camera elevation above the base (degrees)")
        ->check(CLI::Range(-90.0f, 90.0f))->capture_default_str();
    app.add_option("--azimuth", view.azimuthDeg, "camera azimuth (degrees)")->capture_default_str();
    app.add_option("--distance", view.distance, "camera distance in box diagonals")
        ->check(CLI::Range(limits.minDistance, limits.maxDistance))->capture_default_str();
    app.add_option("--fov", view.fovDeg, "vertical field of view (degrees)")
        ->check(CLI::Range(limits.minFov, limits.maxFov))->capture_default_str();
    app.add_option("--light-elevation", lightElevation, "light elevation (degrees)")->capture_default_str();
    app.add_option("--light-azimuth", lightAzimuth, "light azimuth (degrees)")->capture_default_str();
}

Result<std::vector<std::pair<std::string, double>>> parameterOverrides(const TechniqueOptions& o) {
    std::vector<std::pair<std::string, double>> overrides;
    if (o.maxSteps) overrides.emplace_back("max-steps", double(*o.maxSteps));
    for (const std::string& p : o.params) {
        const size_t eq = p.find('=');
        double value = 0;
        const char* begin = p.c_str() + (eq == std::string::npos ? 0 : eq + 1);
        const char* end = p.c_str() + p.size();
        auto [ptr, ec] = std::from_chars(begin, end, value);
        if (eq == std::string::npos || ec != std::errc() || ptr != end)
            return makeError(ErrorKind::BadArgument, "--param '{}': expected NAME=NUMBER", p);
        overrides.emplace_back(p.substr(0, eq), value);
    }
    return overrides;
}

Result<std::unique_ptr<Tracer>> makeTracer(const TechniqueOptions& o,
                                           std::shared_ptr<const Surface> surface) {
    auto info = lookupTechnique(o.name);
    if (!info) return info.error();
    auto overrides = parameterOverrides(o);
    if (!overrides) return overrides.error();
    std::shared_ptr<const MapFile> maps;
    if (!o.mapsPath.empty() && (*info)->buildMaps) {
        auto loaded = loadCheckedMaps(o.mapsPath, *surface);
        if (!loaded) return loaded.error();
        maps = *loaded;  // the cache in loadCheckedMaps outlives every tracer
    }
    auto input = techniqueInput(**info, surface, *overrides, maps.get(), o.mapsPath);
    if (!input) return input.error();
    if (o.backend == "gl") return createGlBackendTracer(**info, *input);
    return (*info)->create(*input);
}

int report(const Error& error) {
    std::fprintf(stderr, "relief: error: %s\n", error.message.c_str());
    return int(error.kind);
}

}  // namespace relief::cli
