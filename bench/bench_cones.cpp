// bench_cones: cone and relaxed-cone maps (safe and faithful builds): build times (wall and
// process CPU, with the load average, since the machine may be shared), error vs iteration cap,
// mean steps vs elevation, and throughput against `exact` and Embree in the same run
// (DESIGN §8). Writes a markdown report (--out, default stdout only) and, with --plots DIR, SVG
// plots of error vs cap and steps vs elevation.
//   bench_cones [--quick] [--threads N] [--out FILE] [--plots DIR] [--size N] [--px N]
//               [--build-sizes N,N,...] [--relaxed-max N] [--builds-only]
// Maps: gen:fbm, gen:peaks6 and a real DEM: an N×N window of the SRTM mosaic
// (../shared/data/earth-srtm-10800x5400.png) centred on the Himalaya, rescaled to [0,1].
#include "bench_common.h"

#include <relief/core/generators.h>
#include <relief/embree/embree_scene.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/compare.h>
#include <relief/report/svg_plot.h>
#include <relief/techniques/common/cone_maps.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>
#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

using namespace relief;

namespace {

struct Config {
    const char* label;
    const char* technique;
    int variant;
    ConeKind kind;
};
constexpr Config kConfigs[] = {{"cone safe", "cone", 0, ConeKind::SafeStrict},
                               {"cone faithful", "cone", 1, ConeKind::FaithfulStrict},
                               {"relaxed safe", "relaxed-cone", 0, ConeKind::SafeStrict},
                               {"relaxed faithful", "relaxed-cone", 1, ConeKind::FaithfulRelaxed}};
constexpr ConeKind kKinds[] = {ConeKind::SafeStrict, ConeKind::FaithfulStrict,
                               ConeKind::FaithfulRelaxed};
const char* kindLabel(ConeKind kind) {
    switch (kind) {
        case ConeKind::SafeStrict: return "safe (cone and relaxed-cone)";
        case ConeKind::FaithfulStrict: return "cone faithful";
        case ConeKind::FaithfulRelaxed: return "relaxed faithful";
    }
    return "?";
}

constexpr const char* kSrtmPath = "/work/shared/data/earth-srtm-10800x5400.png";
constexpr int kHimalayaX = 7980, kHimalayaY = 1860;  // 86° E, 28° N in the 10800×5400 mosaic

// An n×n window of `world` centred near (cx, cy) (moved inside the map), rescaled to [0,1].
Heightfield window(const Heightfield& world, int n, int cx, int cy) {
    const int x0 = std::clamp(cx - n / 2, 0, world.width - n);
    const int y0 = std::clamp(cy - n / 2, 0, world.height - n);
    Heightfield hf{n, n, std::vector<float>(size_t(n) * size_t(n))};
    float lo = 1.0f, hi = 0.0f;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const float v = world.at(x0 + i, y0 + j);
            hf.at(i, j) = v;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    for (float& v : hf.samples) v = hi > lo ? (v - lo) / (hi - lo) : 0.0f;
    return hf;
}

// The heightfields by name: "fbm", "peaks6" (generators, seed 1) and "srtm" (window above).
class Sources {
public:
    std::optional<Heightfield> get(const std::string& name, int n) {
        if (name != "srtm") return *generateHeightfield(name, n, n, 1);
        if (!m_world) {
            auto loaded = loadHeightfield(kSrtmPath);
            if (!loaded.ok()) return std::nullopt;
            m_world = std::move(*loaded);
        }
        if (n > m_world->width || n > m_world->height) return std::nullopt;
        return window(*m_world, n, kHimalayaX, kHimalayaY);
    }

private:
    std::optional<Heightfield> m_world;
};

std::shared_ptr<const Surface> surfaceOf(const Heightfield& hf) {
    auto shared = std::make_shared<const Heightfield>(hf);
    return std::make_shared<const Surface>(shared, 0.1f * float(std::max(hf.width, hf.height)),
                                           EdgeMode::Clamp);
}

double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

struct TimedBuild {
    double wall = 0, cpu = 0;
    std::string load;  // 1-minute load average when the build ended
    std::vector<vec2> cones;
};

TimedBuild timedBuild(const Surface& s, ConeKind kind) {
    TimedBuild b;
    const double cpu0 = processCpuSeconds();
    b.wall = bench::bestSeconds(1, [&] { b.cones = buildCones(s, kind); });
    b.cpu = processCpuSeconds() - cpu0;
    b.load = bench::loadAverage();
    return b;
}

// Builds keyed by (map, size, kind); the quality runs reuse the ones the build table made.
using BuildKey = std::tuple<std::string, int, ConeKind>;
using BuildCache = std::map<BuildKey, TimedBuild>;

std::string buildTable(Sources& sources, const std::vector<std::string>& maps,
                       const std::vector<int>& sizes, int relaxedMax, BuildCache& cache) {
    std::string out = "| map | size | " + std::string(kindLabel(kKinds[0])) + " | " +
                      kindLabel(kKinds[1]) + " | " + kindLabel(kKinds[2]) + " |\n" +
                      "|---|---|---|---|---|\n";
    for (const std::string& name : maps)
        for (int n : sizes) {
            const auto hf = sources.get(name, n);
            if (!hf) continue;
            const auto s = surfaceOf(*hf);
            out += fmt::format("| {} | {}² |", name, n);
            for (ConeKind kind : kKinds) {
                if (kind == ConeKind::FaithfulRelaxed && n > relaxedMax) {
                    out += " — |";
                    continue;
                }
                TimedBuild b = timedBuild(*s, kind);
                out += fmt::format(" {:.2f} / {:.2f} (load {}) |", b.wall, b.cpu, b.load);
                std::fprintf(stderr, "build %s %d %s: wall %.2f s cpu %.2f s load %s\n",
                             name.c_str(), n, kindLabel(kind), b.wall, b.cpu, b.load.c_str());
                cache[{name, n, kind}] = std::move(b);
            }
            out += "\n";
        }
    return out;
}

const std::vector<vec2>& conesFor(BuildCache& cache, const std::string& name, const Surface& s,
                                  ConeKind kind) {
    const BuildKey key{name, s.width(), kind};
    auto found = cache.find(key);
    if (found == cache.end()) found = cache.emplace(key, timedBuild(s, kind)).first;
    return found->second.cones;
}

// The baked maps of a config, as `relief bake` would write them (float32).
TechniqueMaps mapsFor(const Surface& s, const Config& c, const std::vector<vec2>& cones) {
    const ConeEncoding encoding;
    TechniqueMaps maps;
    maps.technique = c.technique;
    maps.parameters = mapParameters(s, c.variant, encoding);
    maps.arrays.push_back(encodeCones(s, cones, encoding));
    return maps;
}

std::unique_ptr<Tracer> makeTracer(std::shared_ptr<const Surface> sp, const Config& c, double cap,
                                   const TechniqueMaps& maps) {
    const TechniqueInfo& info = *findTechnique(c.technique);
    std::vector<std::pair<std::string, double>> params{{"variant", double(c.variant)}};
    if (cap > 0) params.push_back({"max-steps", cap});
    auto values = resolveParams(info, params);
    return std::move(*info.create(TechniqueInput{sp, *values, &maps}));
}

Image<Hit> traceImage(const Tracer& tracer, const std::vector<Ray>& rays, int w, int h) {
    Image<Hit> image(w, h);
    parallelRanges(int64_t(h), 4, [&](int64_t begin, int64_t end) {
        for (int64_t y = begin; y < end; ++y)
            tracer.traceBatch(std::span(rays).subspan(size_t(y) * size_t(w), size_t(w)),
                              std::span(image.pixels).subspan(size_t(y) * size_t(w), size_t(w)));
    });
    return image;
}

std::string tableHeader(const std::string& first, const std::vector<std::string>& columns) {
    std::string out = "| " + first + " |";
    for (const std::string& c : columns) out += " " + c + " |";
    out += "\n|---|";
    for (size_t k = 0; k < columns.size(); ++k) out += "---|";
    return out + "\n";
}

struct QualityResult {
    std::string markdown;
    std::vector<PlotSeries> errorVsCap, stepsVsElevation;
};

// Error vs cap (mean |dt|, wrong %) over the 8 standard elevations, and mean steps vs elevation.
QualityResult qualityTables(const std::string& title, std::shared_ptr<const Surface> sp, int px,
                            const std::function<const std::vector<vec2>&(ConeKind)>& cones) {
    const Surface& s = *sp;
    auto exact = createTracer("exact", sp);
    std::vector<std::vector<Ray>> rays;
    std::vector<Image<Hit>> refs;
    for (float el : kStandardElevations) {
        const Camera cam(OrbitView{el, 30.0f, 1.2f, 45.0f}, s, px, px);
        rays.push_back(primaryRays(cam));
        refs.push_back(traceImage(**exact, rays.back(), px, px));
    }
    std::vector<std::string> capColumns, elevationColumns;
    for (int cap : kStandardCaps) capColumns.push_back(std::to_string(cap));
    for (float el : kStandardElevations) elevationColumns.push_back(fmt::format("{}°", el));
    QualityResult result;
    std::string caps = fmt::format("\n**{}** — mean |Δt| (texels) / wrong-hit % over the 8 "
                                   "elevations, by max-steps\n\n",
                                   title) +
                       tableHeader("technique", capColumns);
    std::string steps = fmt::format("\n**{}** — mean steps per pixel at the default caps, by "
                                    "elevation\n\n",
                                    title) +
                        tableHeader("technique", elevationColumns);
    for (const Config& c : kConfigs) {
        const TechniqueMaps maps = mapsFor(s, c, cones(c.kind));
        PlotSeries errorSeries{c.label, {}, {}}, stepSeries{c.label, {}, {}};
        caps += fmt::format("| {} |", c.label);
        for (int cap : kStandardCaps) {
            auto tracer = makeTracer(sp, c, cap, maps);
            double err = 0, wrong = 0;
            for (size_t e = 0; e < rays.size(); ++e) {
                const ErrorStats st = compareHits(traceImage(*tracer, rays[e], px, px), refs[e]);
                err += st.error.mean / double(rays.size());
                wrong += 100.0 * st.wrongRate() / double(rays.size());
            }
            caps += fmt::format(" {:.3g} / {:.2g} |", err, wrong);
            errorSeries.x.push_back(cap);
            errorSeries.y.push_back(err);
        }
        caps += "\n";
        steps += fmt::format("| {} |", c.label);
        auto tracer = makeTracer(sp, c, 0, maps);
        for (size_t e = 0; e < rays.size(); ++e) {
            const ErrorStats st = compareHits(traceImage(*tracer, rays[e], px, px), refs[e]);
            steps += fmt::format(" {:.1f} |", st.steps.mean);
            stepSeries.x.push_back(kStandardElevations[e]);
            stepSeries.y.push_back(st.steps.mean);
        }
        steps += "\n";
        result.errorVsCap.push_back(std::move(errorSeries));
        result.stepsVsElevation.push_back(std::move(stepSeries));
        std::fprintf(stderr, "quality %s %s done (load %s)\n", title.c_str(), c.label,
                     bench::loadAverage().c_str());
    }
    result.markdown = caps + steps;
    return result;
}

std::string throughputTable(std::shared_ptr<const Surface> sp, int px,
                            const std::function<const std::vector<vec2>&(ConeKind)>& cones) {
    const Surface& s = *sp;
    const Camera cam(OrbitView{40.2f, 30.0f, 1.2f, 45.0f}, s, px, px);
    const std::vector<Ray> rays = bench::tiledPrimaryRays(cam);
    std::vector<Hit> hits(rays.size());
    auto mrays = [&](const std::function<void(size_t, size_t)>& trace) {
        const double sec = bench::bestSeconds(3, [&] { bench::forEachTile(rays.size(), trace); });
        return double(rays.size()) / sec * 1e-6;
    };
    auto techniqueRate = [&](const Tracer& t) {
        return mrays([&](size_t first, size_t count) {
            t.traceBatch(std::span(rays).subspan(first, count),
                         std::span(hits).subspan(first, count));
        });
    };
    std::string out = "| tracer | Mrays/s |\n|---|---|\n";
    auto exact = createTracer("exact", sp);
    out += fmt::format("| exact | {:.2f} |\n", techniqueRate(**exact));
    for (const Config& c : kConfigs) {
        auto tracer = makeTracer(sp, c, 0, mapsFor(s, c, cones(c.kind)));
        out += fmt::format("| {} (default caps) | {:.2f} |\n", c.label, techniqueRate(*tracer));
    }
    auto embree = EmbreeScene::create(s);
    if (embree.ok()) {
        const double r16 = mrays([&](size_t first, size_t count) {
            (*embree)->intersect16(std::span(rays).subspan(first, count),
                                   std::span(hits).subspan(first, count));
        });
        out += fmt::format("| Embree rtcIntersect16 | {:.2f} |\n", r16);
    }
    return out + fmt::format("\n(load after the throughput runs: {})\n", bench::loadAverage());
}

void writePlots(const std::string& dir, const std::string& stem, const std::string& title,
                const QualityResult& q) {
    std::filesystem::create_directories(dir);
    PlotSpec errors{title + ": mean |Δt| vs max-steps (8 elevations)", "max-steps",
                    "mean |Δt| (texels)", true, true};
    std::ofstream(dir + "/" + stem + "-error-vs-cap.svg") << svgLinePlot(errors, q.errorVsCap);
    PlotSpec steps{title + ": mean steps vs elevation (default caps)", "elevation (degrees)",
                   "mean steps per pixel"};
    std::ofstream(dir + "/" + stem + "-steps-vs-elevation.svg")
        << svgLinePlot(steps, q.stepsVsElevation);
}

std::vector<int> parseSizes(const char* text) {
    std::vector<int> sizes;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
        if (int n = 0; bench::parseInt(item.c_str(), n) && n >= 8) sizes.push_back(n);
    return sizes;
}

int finish(const std::string& report, const std::string& outPath) {
    std::printf("%s", report.c_str());
    if (!outPath.empty()) std::ofstream(outPath) << report;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, buildsOnly = false;
    int threads = 2, size = 0, px = 0, relaxedMax = 1024;
    std::string outPath, plotDir;
    std::vector<int> buildSizes;
    for (int k = 1; k < argc; ++k) {
        const bool hasValue = k + 1 < argc;
        if (!std::strcmp(argv[k], "--quick")) quick = true;
        else if (!std::strcmp(argv[k], "--builds-only")) buildsOnly = true;
        else if (!std::strcmp(argv[k], "--threads") && hasValue &&
                 bench::parseInt(argv[++k], threads)) {}
        else if (!std::strcmp(argv[k], "--size") && hasValue && bench::parseInt(argv[++k], size)) {}
        else if (!std::strcmp(argv[k], "--px") && hasValue && bench::parseInt(argv[++k], px)) {}
        else if (!std::strcmp(argv[k], "--relaxed-max") && hasValue &&
                 bench::parseInt(argv[++k], relaxedMax)) {}
        else if (!std::strcmp(argv[k], "--build-sizes") && hasValue)
            buildSizes = parseSizes(argv[++k]);
        else if (!std::strcmp(argv[k], "--out") && hasValue) outPath = argv[++k];
        else if (!std::strcmp(argv[k], "--plots") && hasValue) plotDir = argv[++k];
        else {
            std::fprintf(stderr,
                         "usage: bench_cones [--quick] [--threads N] [--out FILE] [--plots DIR] "
                         "[--size N] [--px N] [--build-sizes N,N,...] [--relaxed-max N] "
                         "[--builds-only]\n");
            return 1;
        }
    }
    const ThreadLimit limit(threads);
    if (size == 0) size = quick ? 256 : 1024;
    if (px == 0) px = quick ? 128 : 256;
    if (buildSizes.empty())
        buildSizes = quick ? std::vector<int>{256, 512}
                           : std::vector<int>{256, 512, 1024, 2048, 4096};
    if (quick) relaxedMax = std::min(relaxedMax, 512);

    std::string report = fmt::format("Machine: {}; threads: {}; load at start: {}; date: {}\n\n",
                                     bench::machineDescription(), threads, bench::loadAverage(),
                                     bench::todayUtc());
    Sources sources;
    BuildCache cache;
    report += "### Build time (wall s / process CPU s, user+sys, 1-minute load when it ended)\n\n" +
              buildTable(sources, {"fbm", "srtm"}, buildSizes, relaxedMax, cache);

    if (buildsOnly) return finish(report, outPath);
    report += fmt::format("\n### Quality ({}×{} px images, {}² maps, depth 0.1·size)\n", px, px,
                          size);
    std::shared_ptr<const Surface> fbm;
    for (const char* name : {"fbm", "peaks6", "srtm"}) {
        const auto hf = sources.get(name, size);
        if (!hf) continue;
        const auto sp = surfaceOf(*hf);
        auto cones = [&](ConeKind kind) -> const std::vector<vec2>& {
            return conesFor(cache, name, *sp, kind);
        };
        const std::string title = fmt::format("{} {}²", name, size);
        const QualityResult q = qualityTables(title, sp, px, cones);
        report += q.markdown;
        if (!plotDir.empty()) writePlots(plotDir, fmt::format("cones-{}-{}", name, size), title, q);
        if (std::string(name) == "fbm") fbm = sp;
    }
    report +=
        fmt::format("\n### Throughput (fbm {}², 40.2°, {}² px, same run)\n\n", size, 2 * px);
    report += throughputTable(fbm, 2 * px, [&](ConeKind kind) -> const std::vector<vec2>& {
        return conesFor(cache, "fbm", *fbm, kind);
    });
    return finish(report, outPath);
}
