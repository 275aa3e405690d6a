// bench_exact_embree: throughput of the reference tracer `exact` against Embree 3 on the same
// triangles (DESIGN §8), in one run and on the same rays: exact through the registry's
// Tracer::traceBatch, rtcIntersect1 per ray, and rtcIntersect16 on coherent 4×4 pixel packets,
// all three parallel over 16×16 pixel tiles. Prints a Markdown table (docs/benchmarks.md).
//
// Exit codes: 0 ok, 1 bad arguments, 2 a heightfield could not be loaded, 4 exact and Embree
// disagree on more than 0.1% of the rays (a bug, not a timing).
#include "bench_common.h"

#include <relief/embree/embree_scene.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/registry.h>

#include <embree3/rtcore_config.h>
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

namespace relief {
namespace {

using namespace relief::bench;

// The bench executables get no RELIEF_SOURCE_DIR from the build; their own path locates data/.
#ifndef RELIEF_SOURCE_DIR
const std::string kSourceDir = [] {
    std::string here = __FILE__;  // <root>/bench/bench_exact_embree.cpp
    for (int up = 0; up < 2 && here.find('/') != std::string::npos; ++up)
        here = here.substr(0, here.rfind('/'));
    return here.empty() ? std::string(".") : here;
}();
#else
const std::string kSourceDir = RELIEF_SOURCE_DIR;
#endif

constexpr const char* kHelp = R"(usage: bench_exact_embree [options]
Throughput of `exact` vs Embree 3 (rtcIntersect1, rtcIntersect16) on the same triangles and rays.
  --quick        small maps and image, one run (smoke test)
  --threads N    worker threads (default: all cores)
  --repeats N    runs per measurement, the best is kept (default 3; --quick: 1)
  --out FILE     also write the Markdown report to FILE
  --data DIR     folder with earth-topology-2048x1024.png (default: <source>/data)
  -h, --help     this text
)";

struct Options {
    bool quick = false;
    int threads = 0;
    int repeats = 0;
    std::string out;
    std::string dataDir = kSourceDir + "/data";
};

bool parseInt(const char* text, int& value) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (!end || *end != '\0' || v < 0 || v > 4096) return false;
    value = int(v);
    return true;
}

// Returns 0 to go on, or an exit code.
int parseOptions(int argc, char** argv, Options& options) {
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        const bool hasValue = k + 1 < argc;
        if (arg == "-h" || arg == "--help") {
            std::fputs(kHelp, stdout);
            return -1;
        } else if (arg == "--quick") {
            options.quick = true;
        } else if (arg == "--threads" && hasValue && parseInt(argv[k + 1], options.threads)) {
            ++k;
        } else if (arg == "--repeats" && hasValue && parseInt(argv[k + 1], options.repeats) &&
                   options.repeats > 0) {
            ++k;
        } else if (arg == "--out" && hasValue) {
            options.out = argv[++k];
        } else if (arg == "--data" && hasValue) {
            options.dataDir = argv[++k];
        } else {
            std::fprintf(stderr, "bench_exact_embree: error: bad or incomplete option '%s'\n%s",
                         arg.c_str(), kHelp);
            return 1;
        }
    }
    if (options.repeats == 0) options.repeats = options.quick ? 1 : 3;
    return 0;
}

struct MapSpec {
    std::string label;
    std::string source;  // a path or gen:NAME:WxH[:seed] (heightfield_io.h)
};

// exact and Embree agree on a ray: same hit/miss, |Δt| ≤ 1e-3 texel (the "exact" contract).
bool agree(const Hit& a, const Hit& b) {
    return a.hit == b.hit && (!a.hit || std::abs(a.t - b.t) <= 1e-3f);
}

struct Row {
    std::string map, view;
    double hitFraction = 0, cellsPerRay = 0;
    double mrays[3] = {0, 0, 0};  // exact, Embree 1, Embree 16
    size_t disagree1 = 0, disagree16 = 0, rays = 0;
};

int run(const Options& options) {
    const ThreadLimit limit(options.threads);
    const int threads = ThreadLimit::current();
    const int imageW = options.quick ? 160 : 1280, imageH = options.quick ? 128 : 1024;
    const float depthRatio = 0.1f;  // DESIGN §1 default
    const float elevations[] = {15.3f, 52.7f};
    OrbitView view;
    view.azimuthDeg = 30.0f;
    view.fovDeg = 45.0f;
    view.distance = 0.9f;  // box diagonals from the box centre: the relief fills most of the frame

    std::vector<MapSpec> maps;
    if (options.quick) {
        maps = {{"fbm 64×64", "gen:fbm:64x64:1"}, {"walls 96×64", "gen:walls:96x64:1"}};
    } else {
        maps = {{"fbm 512×512", "gen:fbm:512x512:1"},
                {"fbm 2048×2048", "gen:fbm:2048x2048:1"},
                {"earth 2048×1024", options.dataDir + "/earth-topology-2048x1024.png"}};
    }

    const std::string date = todayUtc(), machine = machineDescription(), load = loadAverage();
    std::fprintf(stderr, "bench_exact_embree: %d threads, load average %s\n", threads,
                 load.c_str());
    std::vector<Row> rows;
    std::string notes;
    for (const MapSpec& spec : maps) {
        auto hf = loadHeightfield(spec.source);
        if (!hf) {
            std::fprintf(stderr, "bench_exact_embree: error: %s\n", hf.error().message.c_str());
            return 2;
        }
        const float depth = depthRatio * float(std::max(hf->width, hf->height));
        auto surface = std::make_shared<const Surface>(
            std::make_shared<const Heightfield>(std::move(*hf)), depth, EdgeMode::Clamp);
        auto tracer = createTracer("exact", surface);
        RELIEF_CHECK(tracer.ok());
        const auto buildStart = std::chrono::steady_clock::now();
        auto scene = EmbreeScene::create(*surface);
        if (!scene) {
            std::fprintf(stderr, "bench_exact_embree: error: %s\n", scene.error().message.c_str());
            return 4;
        }
        const std::chrono::duration<double> build = std::chrono::steady_clock::now() - buildStart;
        notes += fmt::format("- {}: D = {} texels, Embree scene {} triangles, built in {:.2f} s\n",
                             spec.label, depth, (*scene)->triangleCount(), build.count());

        for (float elevation : elevations) {
            view.elevationDeg = elevation;
            const Camera camera(view, *surface, imageW, imageH);
            const std::vector<Ray> rays = tiledPrimaryRays(camera);
            const std::span<const Ray> all(rays);
            std::vector<Hit> exactHits(rays.size()), hits1(rays.size()), hits16(rays.size());
            const EmbreeScene& embree = **scene;
            const Tracer& exact = **tracer;
            const std::function<void()> methods[3] = {
                [&] {
                    forEachTile(rays.size(), [&](size_t first, size_t n) {
                        exact.traceBatch(all.subspan(first, n),
                                         std::span(exactHits).subspan(first, n));
                    });
                },
                [&] {
                    forEachTile(rays.size(), [&](size_t first, size_t n) {
                        embree.intersect1(all.subspan(first, n), std::span(hits1).subspan(first, n));
                    });
                },
                [&] {
                    forEachTile(rays.size(), [&](size_t first, size_t n) {
                        embree.intersect16(all.subspan(first, n),
                                           std::span(hits16).subspan(first, n));
                    });
                },
            };
            // Interleaved, so that a burst of load from elsewhere hits all three alike.
            double best[3] = {1e300, 1e300, 1e300};
            for (int r = 0; r < options.repeats; ++r)
                for (int m = 0; m < 3; ++m) best[m] = std::min(best[m], bestSeconds(1, methods[m]));

            Row row;
            row.map = spec.label;
            row.view = fmt::format("{}°", elevation);
            row.rays = rays.size();
            size_t hitCount = 0, cells = 0;
            for (size_t k = 0; k < rays.size(); ++k) {
                hitCount += exactHits[k].hit;
                cells += size_t(exactHits[k].steps);
                row.disagree1 += !agree(exactHits[k], hits1[k]);
                row.disagree16 += !agree(exactHits[k], hits16[k]);
            }
            row.hitFraction = double(hitCount) / double(rays.size());
            row.cellsPerRay = double(cells) / double(rays.size());
            for (int m = 0; m < 3; ++m) row.mrays[m] = double(rays.size()) / best[m] * 1e-6;
            std::fprintf(stderr, "  %s, elevation %s: exact %.2f, Embree1 %.2f, Embree16 %.2f "
                         "Mrays/s\n", row.map.c_str(), row.view.c_str(), row.mrays[0],
                         row.mrays[1], row.mrays[2]);
            rows.push_back(row);
        }
    }

    std::string report;
    report += fmt::format("Run {}; {}; {} threads; load average {} at start.\n", date, machine,
                          threads, load);
    report += fmt::format(
        "{}×{} primary rays, orbit camera (azimuth 30°, distance {} box diagonals from the "
        "box centre, vertical fov 45°), depth ratio {}, clamp; Embree {} (RTC_SCENE_FLAG_ROBUST, "
        "build quality high); best of {} interleaved runs; all three methods in this one "
        "run, on the same rays.\n\n",
        imageW, imageH, view.distance, depthRatio, RTC_VERSION_STRING, options.repeats);
    report +=
        "| map | elevation | hits | cells/ray (exact) | exact Mrays/s | Embree1 Mrays/s | "
        "Embree16 Mrays/s | exact/Embree1 | exact/Embree16 | agree exact–Embree1 | "
        "agree exact–Embree16 |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
    bool agreementOk = true;
    for (const Row& r : rows) {
        auto agreement = [&r](size_t disagree) {
            return fmt::format("{:.4f}% ({} differ)", 100.0 * double(r.rays - disagree) /
                                                          double(r.rays), disagree);
        };
        report += fmt::format("| {} | {} | {:.1f}% | {:.0f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | "
                              "{:.2f} | {} | {} |\n",
                              r.map, r.view, 100.0 * r.hitFraction, r.cellsPerRay, r.mrays[0],
                              r.mrays[1], r.mrays[2], r.mrays[0] / r.mrays[1],
                              r.mrays[0] / r.mrays[2], agreement(r.disagree1),
                              agreement(r.disagree16));
        agreementOk = agreementOk && r.disagree1 * 1000 <= r.rays && r.disagree16 * 1000 <= r.rays;
    }
    report += "\n" + notes;
    std::fputs(report.c_str(), stdout);
    if (!options.out.empty()) {
        std::FILE* f = std::fopen(options.out.c_str(), "w");
        if (!f || std::fputs(report.c_str(), f) < 0 || std::fclose(f) != 0) {
            std::fprintf(stderr, "bench_exact_embree: error: cannot write '%s'\n",
                         options.out.c_str());
            return 2;
        }
    }
    if (!agreementOk) {
        std::fprintf(stderr, "bench_exact_embree: error: exact and Embree disagree on more than "
                     "0.1%% of the rays of a view\n");
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
