// bench_quadtree: evidence for issue 3 (quadtree relief mapping, maximum mipmaps).
//   (a) scaling: mean and 99th-percentile steps per ray against map size (fbm 256² … 8192², and
//       the 10800×5400 earth SRTM map when it loads) at the eight standard elevations, for
//       quadtree, quadtree with the paper's never-ascend walk, maxmip, quadtree-oriented and
//       exact; every hit is checked against exact (wrong hits are counted, should be 0);
//   (b) throughput: Mrays/s of the same tracers, exact, Embree rtcIntersect1 and rtcIntersect16,
//       in one run on the same 1280×1024 primary rays, at 1024² and 4096².
// Writes a Markdown report (stdout, and --out FILE) and an SVG plot of (a) (--svg FILE).
//
// Exit codes: 0 ok, 1 bad arguments, 2 a file could not be written, 4 a tracer disagrees with
// exact (a bug, not a timing).
#include <embree3/rtcore_config.h>
#include <fmt/format.h>
#include <relief/core/generators.h>
#include <relief/core/stats.h>
#include <relief/embree/embree_scene.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/exact/exact.h>
#include <relief/techniques/maxmip/maxmip.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "bench_common.h"

namespace relief {
namespace {

using namespace relief::bench;

constexpr const char* kHelp = R"(usage: bench_quadtree [options]
Steps per ray vs map size, and throughput vs Embree, of quadtree, maxmip, quadtree-oriented.
  --quick        small maps and images, one run (no 8192² or earth map)
  --threads N    worker threads (default: all cores)
  --repeats N    timed runs per measurement, the best is kept (default 3; --quick: 1)
  --out FILE     also write the Markdown report to FILE
  --svg FILE     write the steps-vs-size plot to FILE
  --data DIR     folder with earth-srtm-10800x5400.png (default: <source>/../shared/data)
  -h, --help     this text
)";

struct Options : CommonOptions {
    std::string svg;
};

// Returns 0 to go on, -1 after --help, or an exit code.
int parseOptions(int argc, char** argv, Options& options) {
    options.dataDir = kSourceDir + "/../shared/data";
    return bench::parseOptions(argc, argv, "bench_quadtree", kHelp, options, {{"--svg", nullptr, &options.svg}});
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---- the tracers, sharing one max pyramid -------------------------------------------------

struct Method {
    std::string name;
    std::unique_ptr<Tracer> tracer;
};

struct Built {
    std::vector<Method> methods;  // exact last
    double pyramidSeconds = 0, orientedSeconds = 0;
    size_t pyramidBytes = 0, orientedBytes = 0;
};

Built buildMethods(const std::shared_ptr<const Surface>& surface) {
    Built b;
    auto start = std::chrono::steady_clock::now();
    const VertexGrid vertices(*surface);
    auto pyramid = std::make_shared<const MaxPyramid>(vertices, PyramidLayout::of(*surface));
    b.pyramidSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    auto oriented = std::make_shared<const OrientedMaps>(vertices, pyramid);
    b.orientedSeconds = secondsSince(start);
    b.pyramidBytes = pyramid->bytes();
    b.orientedBytes = oriented->planes.bytes();
    b.methods.push_back(
        {"quadtree", makeBatchTracer(QuadtreeTracer(surface, pyramid, Ascent::Parent, {}))});
    b.methods.push_back(
        {"quadtree ascend=0", makeBatchTracer(QuadtreeTracer(surface, pyramid, Ascent::None, {}))});
    b.methods.push_back({"maxmip", makeBatchTracer(MaxmipTracer(surface, pyramid, {}))});
    b.methods.push_back(
        {"quadtree-oriented", makeBatchTracer(QuadtreeOrientedTracer(surface, oriented, {}))});
    b.methods.push_back({"exact", makeBatchTracer(ExactTracer(surface))});
    return b;
}

// Parallel over 16×16-pixel tiles, the same work items as the Embree runs.
void traceTiles(const Tracer& tracer, std::span<const Ray> rays, std::span<Hit> hits) {
    forEachTile(rays.size(), [&](size_t first, size_t n) {
        tracer.traceBatch(rays.subspan(first, n), hits.subspan(first, n));
    });
}

bool agree(const Hit& a, const Hit& b) {
    return a.hit == b.hit && (!a.hit || std::abs(a.t - b.t) <= 1e-3f);
}

std::shared_ptr<const Surface> clampSurface(Heightfield hf, float depthRatio) {
    const float depth = depthRatio * float(std::max(hf.width, hf.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(hf)),
                                           depth, EdgeMode::Clamp);
}

OrbitView orbit(float elevation) {
    OrbitView view;
    view.elevationDeg = elevation;
    view.azimuthDeg = 30.0f;
    view.fovDeg = 45.0f;
    view.distance = 0.6f;  // box diagonals from the centre: the relief fills most of the frame
    return view;
}

// ---- (a) steps against size -------------------------------------------------------------

struct StepRow {
    std::string map;
    int64_t pixels = 0;
    float elevation = 0;
    std::vector<Summary> steps;  // per method, over the rays that enter the box
    std::vector<size_t> wrong;   // per method, against exact
};

struct ScalingResult {
    std::vector<std::string> methods;
    std::vector<StepRow> rows;
    std::string notes;
    size_t wrong = 0;
};

void scaleOneMap(const std::string& label, Heightfield hf, int imageW, int imageH,
                 ScalingResult& result) {
    const int64_t pixels = int64_t(hf.width) * hf.height;
    const auto surface = clampSurface(std::move(hf), 0.1f);
    Built built = buildMethods(surface);
    if (result.methods.empty())
        for (const Method& m : built.methods) result.methods.push_back(m.name);
    result.notes += fmt::format(
        "- {}: max pyramid {:.0f} MB built in {:.3f} s; oriented planes {:.0f} MB built in "
        "{:.2f} s\n",
        label, double(built.pyramidBytes) / 1e6, built.pyramidSeconds,
        double(built.orientedBytes) / 1e6, built.orientedSeconds);
    for (float elevation : kStandardElevations) {
        const Camera camera(orbit(elevation), *surface, imageW, imageH);
        const std::vector<Ray> rays = tiledPrimaryRays(camera);
        std::vector<std::vector<Hit>> hits(built.methods.size(), std::vector<Hit>(rays.size()));
        for (size_t m = 0; m < built.methods.size(); ++m)
            traceTiles(*built.methods[m].tracer, rays, hits[m]);
        const std::vector<Hit>& reference = hits.back();
        StepRow row{label, pixels, elevation, {}, {}};
        for (size_t m = 0; m < built.methods.size(); ++m) {
            std::vector<double> steps;
            size_t wrong = 0;
            for (size_t k = 0; k < rays.size(); ++k) {
                if (surface->clip(rays[k]).empty()) continue;
                steps.push_back(double(hits[m][k].steps));
                wrong += !agree(hits[m][k], reference[k]);
            }
            row.steps.push_back(summarize(std::move(steps)));
            row.wrong.push_back(wrong);
            result.wrong += wrong;
        }
        std::fprintf(stderr, "  %s %5.1f°: quadtree %.1f, maxmip %.1f, oriented %.1f, exact %.0f\n",
                     label.c_str(), elevation, row.steps[0].mean, row.steps[2].mean,
                     row.steps[3].mean, row.steps[4].mean);
        result.rows.push_back(std::move(row));
    }
}

ScalingResult runScaling(const Options& options) {
    ScalingResult result;
    const int imageW = options.quick ? 160 : 320, imageH = options.quick ? 128 : 256;
    std::vector<int> sizes = {256, 512, 1024, 2048, 4096};
    if (options.quick)
        sizes = {256, 512, 1024};
    else
        sizes.push_back(8192);
    for (int size : sizes) {
        auto start = std::chrono::steady_clock::now();
        auto hf = generateHeightfield("fbm", size, size, 1);
        RELIEF_CHECK(hf.ok());
        std::fprintf(stderr, "bench_quadtree: fbm %d² generated in %.1f s\n", size,
                     secondsSince(start));
        scaleOneMap(fmt::format("fbm {}²", size), std::move(*hf), imageW, imageH, result);
    }
    if (!options.quick) {
        const std::string path = options.dataDir + "/earth-srtm-10800x5400.png";
        auto hf = loadHeightfield(path);
        if (hf) {
            scaleOneMap("earth 10800×5400", std::move(*hf), imageW, imageH, result);
        } else {
            std::fprintf(stderr, "bench_quadtree: skipping the earth map: %s\n",
                         hf.error().message.c_str());
            result.notes += "- earth 10800×5400 skipped: " + hf.error().message + "\n";
        }
    }
    return result;
}

std::string scalingTables(const ScalingResult& r, int imageW, int imageH) {
    std::string text = fmt::format(
        "Steps per ray (main-loop iterations: nodes and cells tested; exact: cells) over the "
        "{}×{} primary rays that enter the box, orbit camera at azimuth 30°, 0.6 box diagonals "
        "from the centre, fov 45°, depth 0.1 × size, clamp. Each cell is mean / p99.\n\n",
        imageW, imageH);
    for (float elevation : kStandardElevations) {
        text += fmt::format("**Elevation {}°**\n\n| map | log2 p |", elevation);
        for (const std::string& m : r.methods) text += " " + m + " |";
        text += " wrong hits |\n|---|---|";
        for (size_t m = 0; m < r.methods.size(); ++m) text += "---|";
        text += "---|\n";
        for (const StepRow& row : r.rows) {
            if (row.elevation != elevation) continue;
            size_t wrong = 0;
            text += fmt::format("| {} | {:.1f} |", row.map, std::log2(double(row.pixels)));
            for (size_t m = 0; m < row.steps.size(); ++m) {
                text += fmt::format(" {:.1f} / {:.0f} |", row.steps[m].mean, row.steps[m].p99);
                wrong += row.wrong[m];
            }
            text += fmt::format(" {} |\n", wrong);
        }
        text += "\n";
    }
    return text + r.notes;
}

// ---- the SVG plot of (a) ------------------------------------------------------------------

struct Series {
    std::string label, color, dash;
    std::vector<std::pair<double, double>> points;  // (log2 p, steps)
};

// One panel of the plot: axes, grid, polylines and legend, at horizontal offset x0.
std::string svgPanel(double x0, const std::string& title, bool logY, double yMax,
                     const std::vector<Series>& series, bool legendLow) {
    const double w = 520, h = 430, left = 55, right = 10, top = 50, bottom = 50;
    const double lp0 = 16, lp1 = 26.5;
    const double y0 = logY ? std::log10(5.0) : 0.0, y1 = logY ? std::log10(yMax) : yMax;
    auto px = [&](double lp) { return x0 + left + (lp - lp0) / (lp1 - lp0) * (w - left - right); };
    auto py = [&](double s) {
        const double v = logY ? std::log10(std::max(s, 5.0)) : s;
        return top + (1.0 - (v - y0) / (y1 - y0)) * (h - top - bottom);
    };
    std::string svg =
        fmt::format("<text x=\"{}\" y=\"30\" font-size=\"14\">{}</text>\n", x0 + left, title);
    std::vector<double> ticks;
    if (logY) {
        for (double t = 5.0; t <= yMax * 1.001; t *= 10.0)
            for (double m : {1.0, 2.0}) ticks.push_back(t * m);
    } else {
        for (double t = 0.0; t <= yMax + 1e-9; t += 5.0) ticks.push_back(t);
    }
    for (double t : ticks) {
        if (t > yMax * 1.001) continue;
        svg += fmt::format(
            "<line x1=\"{0:.1f}\" x2=\"{1:.1f}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"#ddd\"/>"
            "<text x=\"{3:.1f}\" y=\"{4:.1f}\" text-anchor=\"end\">{5}</text>\n",
            x0 + left, x0 + w - right, py(t), x0 + left - 5, py(t) + 4, t);
    }
    for (int lp = 16; lp <= 26; lp += 2)
        svg += fmt::format(
            "<line x1=\"{0:.1f}\" x2=\"{0:.1f}\" y1=\"{1}\" y2=\"{2}\" stroke=\"#eee\"/>"
            "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4}²</text>\n",
            px(lp), top, h - bottom, h - bottom + 16, 1 << (lp / 2));
    svg += fmt::format(
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">map size (log scale: "
        "log2 p from 16 to 26)</text>\n",
        x0 + (left + w - right) / 2, h - 12);
    const double legendX = legendLow ? x0 + w - right - 190 : x0 + left + 10;
    int labels = 0;
    for (const Series& s : series) labels += !s.label.empty();
    double ly = legendLow ? h - bottom - 12 - 16.0 * labels : top + 12;
    for (const Series& s : series) {
        std::string points;
        for (const auto& [lp, steps] : s.points)
            points += fmt::format("{:.1f},{:.1f} ", px(lp), py(steps));
        svg += fmt::format(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\" "
            "stroke-dasharray=\"{}\"/>\n",
            points, s.color, s.dash);
        if (s.label.empty()) continue;
        svg += fmt::format(
            "<line x1=\"{0:.1f}\" x2=\"{1:.1f}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"{3}\" "
            "stroke-width=\"2\" stroke-dasharray=\"{4}\"/><text x=\"{5:.1f}\" y=\"{6:.1f}\">{7}"
            "</text>\n",
            legendX, legendX + 28, ly, s.color, s.dash, legendX + 34, ly + 4, s.label);
        ly += 16;
    }
    return svg;
}

// Left: mean steps of the hierarchical walks (linear y: a straight line is ∝ log p). Right:
// 99th percentile at the grazing elevation, with exact (log y: slope 1/2 per log2 p is √p).
std::string scalingSvg(const ScalingResult& r) {
    const char* colors[] = {"#1f77b4", "#9467bd", "#2ca02c", "#ff7f0e", "#d62728"};
    const float elevations[] = {2.9f, 27.8f, 90.0f};
    const char* dashes[] = {"", "8,4", "2,3"};
    auto points = [&](size_t m, float elevation, bool p99) {
        std::vector<std::pair<double, double>> pts;
        for (const StepRow& row : r.rows)
            if (row.elevation == elevation && row.map.rfind("fbm", 0) == 0)
                pts.push_back(
                    {std::log2(double(row.pixels)), p99 ? row.steps[m].p99 : row.steps[m].mean});
        return pts;
    };
    std::vector<Series> means, tails;
    double meanMax = 10.0, tailMax = 100.0;
    for (size_t m = 0; m < r.methods.size(); ++m) {
        const bool exact = r.methods[m] == "exact";
        for (size_t e = 0; e < std::size(elevations) && !exact; ++e) {
            Series s{e == 0 ? r.methods[m] : "", colors[m % 5], dashes[e],
                     points(m, elevations[e], false)};
            for (const auto& pt : s.points) meanMax = std::max(meanMax, pt.second);
            means.push_back(std::move(s));
        }
        Series tail{r.methods[m], colors[m % 5], "", points(m, elevations[0], true)};
        for (const auto& pt : tail.points) tailMax = std::max(tailMax, pt.second);
        tails.push_back(std::move(tail));
    }
    const double w = 1060, h = 470;
    std::string svg = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
        "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
        "fill=\"white\"/>\n",
        w, h);
    svg += svgPanel(0, "Mean steps per ray (fbm; solid 2.9°, dashed 27.8°, dotted 90°)", false,
                    5.0 * std::ceil(meanMax / 5.0), means, true);
    svg += svgPanel(530, "99th percentile of steps at 2.9° (log scale)", true,
                    std::pow(10.0, std::ceil(std::log10(tailMax))), tails, false);
    svg += fmt::format(
        "<text x=\"10\" y=\"{}\" font-size=\"11\" fill=\"#555\">Depth 0.1·size, "
        "clamp, orbit camera 0.6 box diagonals from the centre, azimuth 30°, fov "
        "45°; steps = nodes and cells tested (exact: cells).</text>\n",
        h - 2);
    return svg + "</svg>\n";
}

// ---- (b) throughput -----------------------------------------------------------------------

struct SpeedRow {
    std::string map;
    float elevation = 0;
    std::vector<double> mrays;  // per column
    size_t wrong = 0;           // tracer hits that disagree with exact (all tracers)
};

struct SpeedResult {
    std::vector<std::string> columns;
    std::vector<SpeedRow> rows;
    std::string notes;
};

void speedOneMap(int size, const Options& options, SpeedResult& result) {
    const int imageW = options.quick ? 320 : 1280, imageH = options.quick ? 256 : 1024;
    auto hf = generateHeightfield("fbm", size, size, 1);
    RELIEF_CHECK(hf.ok());
    const auto surface = clampSurface(std::move(*hf), 0.1f);
    Built built = buildMethods(surface);
    auto start = std::chrono::steady_clock::now();
    auto scene = EmbreeScene::create(*surface);
    RELIEF_CHECK(scene.ok());
    result.notes += fmt::format(
        "- fbm {}²: Embree scene {} triangles built in {:.1f} s; max pyramid built in {:.3f} s, "
        "oriented planes in {:.2f} s ({} threads)\n",
        size, (*scene)->triangleCount(), secondsSince(start), built.pyramidSeconds,
        built.orientedSeconds, ThreadLimit::current());
    if (result.columns.empty()) {
        for (const Method& m : built.methods) result.columns.push_back(m.name);
        result.columns.push_back("Embree rtcIntersect1");
        result.columns.push_back("Embree rtcIntersect16");
    }
    const float elevations[] = {15.3f, 40.2f, 65.1f};
    for (float elevation : elevations) {
        const Camera camera(orbit(elevation), *surface, imageW, imageH);
        const std::vector<Ray> rays = tiledPrimaryRays(camera);
        const std::span<const Ray> all(rays);
        std::vector<std::vector<Hit>> hits(result.columns.size(), std::vector<Hit>(rays.size()));
        std::vector<std::function<void()>> runs;
        for (size_t m = 0; m < built.methods.size(); ++m)
            runs.push_back([&, m] { traceTiles(*built.methods[m].tracer, all, hits[m]); });
        const EmbreeScene& embree = **scene;
        const size_t e1 = built.methods.size(), e16 = e1 + 1;
        runs.push_back([&] {
            forEachTile(rays.size(), [&](size_t first, size_t n) {
                embree.intersect1(all.subspan(first, n), std::span(hits[e1]).subspan(first, n));
            });
        });
        runs.push_back([&] {
            forEachTile(rays.size(), [&](size_t first, size_t n) {
                embree.intersect16(all.subspan(first, n), std::span(hits[e16]).subspan(first, n));
            });
        });
        // Interleaved, so that a burst of load from elsewhere hits all alike.
        std::vector<double> best(runs.size(), 1e300);
        for (int r = 0; r < options.repeats; ++r)
            for (size_t m = 0; m < runs.size(); ++m)
                best[m] = std::min(best[m], bestSeconds(1, runs[m]));
        SpeedRow row{fmt::format("fbm {}²", size), elevation, {}, 0};
        for (size_t m = 0; m < runs.size(); ++m)
            row.mrays.push_back(double(rays.size()) / best[m] * 1e-6);
        const std::vector<Hit>& reference = hits[e1 - 1];
        for (size_t m = 0; m + 1 < e1; ++m)
            for (size_t k = 0; k < rays.size(); ++k) row.wrong += !agree(hits[m][k], reference[k]);
        std::fprintf(stderr, "  fbm %d² %.1f°: quadtree %.2f, maxmip %.2f, Embree1 %.2f Mrays/s\n",
                     size, elevation, row.mrays[0], row.mrays[2], row.mrays[e1]);
        result.rows.push_back(std::move(row));
    }
}

std::string speedTables(const SpeedResult& r, int imageW, int imageH, int repeats) {
    std::string text = fmt::format(
        "{}×{} primary rays (tiles of 16×16, Embree packets of 4×4), same camera as above at "
        "three elevations; Embree {} (robust, high build quality) on the same triangles; best of "
        "{} interleaved runs.\n\n| map | elevation |",
        imageW, imageH, RTC_VERSION_STRING, repeats);
    for (const std::string& c : r.columns) text += " " + c + " |";
    text += " quadtree / Embree1 | quadtree / Embree16 | wrong hits |\n|---|---|";
    for (size_t c = 0; c < r.columns.size() + 3; ++c) text += "---|";
    text += "\n";
    const size_t e1 = r.columns.size() - 2, e16 = e1 + 1;
    for (const SpeedRow& row : r.rows) {
        text += fmt::format("| {} | {}° |", row.map, row.elevation);
        for (double v : row.mrays) text += fmt::format(" {:.2f} |", v);
        text += fmt::format(" {:.2f} | {:.2f} | {} |\n", row.mrays[0] / row.mrays[e1],
                            row.mrays[0] / row.mrays[e16], row.wrong);
    }
    return text + "\n" + r.notes;
}

int run(const Options& options) {
    const ThreadLimit limit(options.threads);
    const int threads = ThreadLimit::current();
    const std::string load = loadAverage();
    std::fprintf(stderr, "bench_quadtree: %d threads, load average %s\n", threads, load.c_str());
    std::string report =
        fmt::format("Run {}; {}; {} threads; load average {} at start{}.\n\n", todayUtc(),
                    machineDescription(), threads, load, options.quick ? "; --quick" : "");
    const ScalingResult scaling = runScaling(options);
    report += "### Steps per ray against map size\n\n" +
              scalingTables(scaling, options.quick ? 160 : 320, options.quick ? 128 : 256);
    SpeedResult speed;
    for (int size : options.quick ? std::vector<int>{256, 1024} : std::vector<int>{1024, 4096})
        speedOneMap(size, options, speed);
    report += "\n### Throughput\n\n" + speedTables(speed, options.quick ? 320 : 1280,
                                                   options.quick ? 256 : 1024, options.repeats);
    std::fputs(report.c_str(), stdout);
    auto write = [](const std::string& path, const std::string& text) {
        std::FILE* f = std::fopen(path.c_str(), "w");
        const bool ok = f && std::fputs(text.c_str(), f) >= 0;
        if (f && std::fclose(f) != 0) return false;
        if (!ok) std::fprintf(stderr, "bench_quadtree: error: cannot write '%s'\n", path.c_str());
        return ok;
    };
    if (!options.out.empty() && !write(options.out, report)) return 2;
    if (!options.svg.empty() && !write(options.svg, scalingSvg(scaling))) return 2;
    size_t wrong = scaling.wrong;
    for (const SpeedRow& row : speed.rows) wrong += row.wrong;
    if (wrong != 0) {
        std::fprintf(stderr, "bench_quadtree: error: %zu hits disagree with exact\n", wrong);
        return 4;
    }
    return 0;
}

}  // namespace
}  // namespace relief

int main(int argc, char** argv) {
    relief::Options options;
    if (const int code = relief::parseOptions(argc, argv, options); code != 0)
        return code < 0 ? 0 : code;
    return relief::run(options);
}
