// bench_exact_embree: throughput of the reference tracer `exact` against Embree 3 on the same
// triangles (DESIGN §8), in one run and on the same rays: exact through the registry's
// Tracer::traceBatch, rtcIntersect1 per ray, and rtcIntersect16 on coherent 4×4 pixel packets,
// all three parallel over 16×16 pixel tiles. Prints a Markdown table (docs/benchmarks-exact-embree.md).
//
// Exit codes: 0 ok, 1 bad arguments, 2 a heightfield could not be loaded, 4 exact and Embree
// disagree on more than 0.1% of the rays of a view, or --judge found exact wrong (a bug, not a
// timing).
#include "bench_common.h"
// The double-precision oracle and the classification of disagreements the tests use (--judge).
#include "../tests/support/brute_force.h"

#include <relief/embree/embree_scene.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/registry.h>

#include <embree3/rtcore_config.h>
#include <fmt/format.h>

#include <cfloat>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

namespace relief {
namespace {

using namespace relief::bench;

constexpr const char* kHelp = R"(usage: bench_exact_embree [options]
Throughput of `exact` vs Embree 3 (rtcIntersect1, rtcIntersect16) on the same triangles and rays.
  --quick        small maps and image, one run (smoke test)
  --threads N    worker threads (default: all cores)
  --repeats N    runs per measurement, the best is kept (default 3; --quick: 1)
  --out FILE     also write the Markdown report to FILE
  --data DIR     folder with earth-topology-2048x1024.png (default: <source>/data)
  --judge        classify up to 32 exact-Embree differences per view and peer with the
                 double-precision brute force of tests/support/brute_force.h (slow on big maps)
  -h, --help     this text
)";

struct Options : CommonOptions {
    bool judge = false;
};

// Returns 0 to go on, -1 after --help, or an exit code.
int parseOptions(int argc, char** argv, Options& options) {
    options.dataDir = kSourceDir + "/data";
    return bench::parseOptions(argc, argv, "bench_exact_embree", kHelp, options, {{"--judge", &options.judge}});
}

struct MapSpec {
    std::string label;
    std::string source;  // a path or gen:NAME:WxH[:seed] (heightfield_io.h)
};

// exact and Embree agree on a ray: same hit/miss, |Δt| ≤ 1e-3 texel (the "exact" contract).
bool agree(const Hit& a, const Hit& b) {
    return a.hit == b.hit && (!a.hit || std::abs(a.t - b.t) <= 1e-3f);
}

// How exact and one Embree call differ over a view.
struct Differences {
    size_t hitMiss = 0;                          // one hits, the other misses
    size_t tOnly = 0;                            // both hit, |Δt| > 1e-3
    double maxDt = 0.0, maxDtUlps = 0.0;         // over tOnly: texels, and float ulps of t
    std::vector<size_t> rays;                    // indices of the differing rays
    size_t judged = 0, kinds[4] = {0, 0, 0, 0};  // --judge: counts by Disagreement

    size_t count() const { return hitMiss + tOnly; }
    void add(size_t k, const Hit& exact, const Hit& peer) {
        if (agree(exact, peer)) return;
        rays.push_back(k);
        if (exact.hit != peer.hit) {
            ++hitMiss;
            return;
        }
        ++tOnly;
        const double dt = std::abs(double(exact.t) - double(peer.t));
        maxDt = std::max(maxDt, dt);
        maxDtUlps = std::max(maxDtUlps, dt / (double(exact.t) * double(FLT_EPSILON)));
    }
};

// Classifies up to `limit` differing rays in parallel: the worst half (hit/miss first, then by
// |Δt|) and the other half spread evenly over the rest.
void judgeDifferences(const BruteForceTracer& oracle, std::span<const Ray> rays,
                      std::span<const Hit> exact, std::span<const Hit> peer, size_t limit,
                      Differences& d) {
    std::vector<size_t> order = d.rays;
    auto severity = [&](size_t k) {
        return exact[k].hit != peer[k].hit ? 1e30 : std::abs(double(exact[k].t) - peer[k].t);
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return severity(a) > severity(b); });
    std::vector<size_t> picked(order.begin(), order.begin() + std::min(limit / 2, order.size()));
    const size_t worst = picked.size(), rest = order.size() - worst,
                 spread = std::min(limit - worst, rest);
    for (size_t k = 0; k < spread; ++k) picked.push_back(order[worst + k * rest / spread]);
    std::vector<Disagreement> kinds(picked.size());
    parallelRanges(int64_t(picked.size()), 1, [&](int64_t begin, int64_t end) {
        for (int64_t k = begin; k < end; ++k) {
            const size_t r = picked[size_t(k)];
            kinds[size_t(k)] = classifyDisagreement(oracle, rays[r], exact[r].hit, exact[r].t,
                                                    peer[r].hit, peer[r].t);
        }
    });
    d.judged = picked.size();
    for (Disagreement kind : kinds) ++d.kinds[int(kind)];
    for (size_t k = 0; k < std::min<size_t>(2, picked.size()); ++k) {
        const size_t r = picked[k];
        const BruteHit b = oracle.trace(rays[r]);
        std::fprintf(stderr,
                     "    worst: o=(%a, %a, %a) d=(%a, %a, %a): exact %d t=%.7g, Embree %d "
                     "t=%.7g, brute force %d t=%.9g: %s\n",
                     rays[r].origin.x, rays[r].origin.y, rays[r].origin.z, rays[r].direction.x,
                     rays[r].direction.y, rays[r].direction.z, exact[r].hit, exact[r].t,
                     peer[r].hit, peer[r].t, b.hit, b.t, toString(kinds[k]));
    }
}

struct Row {
    std::string map, view;
    double hitFraction = 0, cellsPerRay = 0;
    double mrays[3] = {0, 0, 0};  // exact, Embree 1, Embree 16
    Differences diff1, diff16;
    size_t rays = 0;
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
    view.distance = 0.6f;  // box diagonals from the box centre: the relief fills most of the frame

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
        std::unique_ptr<BruteForceTracer> oracle;
        if (options.judge) oracle = std::make_unique<BruteForceTracer>(*surface);

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
                        embree.intersect1(all.subspan(first, n),
                                          std::span(hits1).subspan(first, n));
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
                row.diff1.add(k, exactHits[k], hits1[k]);
                row.diff16.add(k, exactHits[k], hits16[k]);
            }
            if (oracle) {
                judgeDifferences(*oracle, rays, exactHits, hits1, 32, row.diff1);
                judgeDifferences(*oracle, rays, exactHits, hits16, 32, row.diff16);
            }
            row.hitFraction = double(hitCount) / double(rays.size());
            row.cellsPerRay = double(cells) / double(rays.size());
            for (int m = 0; m < 3; ++m) row.mrays[m] = double(rays.size()) / best[m] * 1e-6;
            std::fprintf(stderr,
                         "  %s, elevation %s: exact %.2f, Embree1 %.2f, Embree16 %.2f "
                         "Mrays/s\n",
                         row.map.c_str(), row.view.c_str(), row.mrays[0], row.mrays[1],
                         row.mrays[2]);
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
    std::string differences;
    for (const Row& r : rows) {
        auto agreement = [&r](const Differences& d) {
            return fmt::format("{:.4f}%", 100.0 * double(r.rays - d.count()) / double(r.rays));
        };
        report += fmt::format(
            "| {} | {} | {:.1f}% | {:.0f} | {:.2f} | {:.2f} | {:.2f} | {:.3f} | {:.3f} | {} | {} "
            "|\n",
            r.map, r.view, 100.0 * r.hitFraction, r.cellsPerRay, r.mrays[0], r.mrays[1], r.mrays[2],
            r.mrays[0] / r.mrays[1], r.mrays[0] / r.mrays[2], agreement(r.diff1),
            agreement(r.diff16));
        for (const auto& [peer, d] : {std::pair{"Embree1", &r.diff1}, {"Embree16", &r.diff16}}) {
            differences += fmt::format(
                "- {} {}, exact vs {}: {} of {} rays differ: {} hit/miss, {} with |Δt| > 1e-3 "
                "(max {:.2g} texel = {:.0f} ulps of t)",
                r.map, r.view, peer, d->count(), r.rays, d->hitMiss, d->tOnly, d->maxDt,
                d->maxDtUlps);
            if (d->judged)
                differences += fmt::format(
                    "; brute force on {}: {} ill-conditioned, {} Embree wrong, {} exact decided "
                    "by rounding, {} unexplained",
                    d->judged, d->kinds[int(Disagreement::IllConditioned)],
                    d->kinds[int(Disagreement::PeerWrong)],
                    d->kinds[int(Disagreement::ExactRounding)],
                    d->kinds[int(Disagreement::Unexplained)]);
            differences += "\n";
            agreementOk = agreementOk && d->count() * 1000 <= r.rays &&
                          d->kinds[int(Disagreement::Unexplained)] == 0;
        }
    }
    report +=
        "\nDifferences (same hit/miss and |Δt| ≤ 1e-3 texel count as agreement):\n\n" + differences;
    report += "\nScenes:\n\n" + notes;
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
        std::fprintf(stderr,
                     "bench_exact_embree: error: exact and Embree disagree on more than "
                     "0.1%% of the rays of a view, or the brute force found exact wrong\n");
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
