// bench_safety: precomputed safety shapes (safety-sd, safety-cc) measured as in the paper's §8 on
// our CPU, in one run: (1) precomputation times 256²…4096² (and the earth map when asked);
// (2) Fig. 29 / Table 1: NA (`exact`), LS (`linear`), RC (`relaxed-cone`, when registered), SD
// and CC with and without φ_max = −45°, at 256², 512², 1024²: time and wrong-pixel rate against
// `exact`; (3) Mrays/s of the same rays against Embree rtcIntersect1 and rtcIntersect16.
// Prints Markdown (docs/safety.md).
#include "bench_common.h"

#include <relief/embree/embree_scene.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/compare.h>
#include <relief/techniques/registry.h>
#include <relief/techniques/safety_common/safety_maps.h>
#include <relief/techniques/safety_common/safety_march.h>

#include <fmt/format.h>

#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

namespace relief {
namespace {

using namespace relief::bench;

constexpr const char* kHelp = R"(usage: bench_safety [options]
Precomputed safety shapes (safety-sd, safety-cc) against NA, LS, RC and Embree, one run.
  --quick        small maps and image, one repeat (smoke test)
  --threads N    worker threads (default 2)
  --repeats N    timed runs per measurement, best kept (default 3; --quick: 1)
  --sizes LIST   precompute sizes, comma-separated (default 256,512,1024,2048,4096)
  --only WHAT    precompute | compare (default: both)
  --compare LIST map sizes of the comparison (default 256,512,1024; --quick: 64,128)
  --only exterior  only the exterior-ray section (§6.2): cyl_ext / cone_ext build times and
                 the rendering gain over the all-ray maps per elevation
  --ext-sizes LIST  exterior build sizes (default 256,512,1024; --quick: 64,128)
  --cone-ext-max N  largest size for the cone_ext build (default 512)
  --gain-size N  map size of the exterior rendering-gain table (default 512; --quick: 128)
  --ext-map GEN  built-in generator of the exterior section (default fbm; e.g. peaks6, a smoother
                 relief where exterior rays gain more)
  --earth FILE   also time the precomputation on this heightfield (e.g. the 10800x5400 SRTM)
  --out FILE     also write the Markdown report to FILE
  -h, --help     this text
)";

struct Options {
    bool quick = false;
    int threads = 2;
    int repeats = 0;
    std::vector<int> sizes = {256, 512, 1024, 2048, 4096};
    std::vector<int> compare = {256, 512, 1024};
    std::string earth, out, only;
    std::vector<int> extSizes = {256, 512, 1024};
    int coneExtMax = 512;
    int gainSize = 512;
    std::string extMap = "fbm";
};

std::vector<int> parseList(const char* p) {
    std::vector<int> v;
    while (*p) {
        v.push_back(std::atoi(p));
        while (*p && *p != ',') ++p;
        if (*p == ',') ++p;
    }
    return v;
}

int parseOptions(int argc, char** argv, Options& o) {
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        const bool value = k + 1 < argc;
        if (arg == "-h" || arg == "--help") {
            std::fputs(kHelp, stdout);
            return -1;
        } else if (arg == "--quick") {
            o.quick = true;
        } else if (arg == "--threads" && value) {
            o.threads = std::atoi(argv[++k]);
        } else if (arg == "--repeats" && value) {
            o.repeats = std::max(1, std::atoi(argv[++k]));
        } else if (arg == "--sizes" && value) {
            o.sizes = parseList(argv[++k]);
        } else if (arg == "--compare" && value) {
            o.compare = parseList(argv[++k]);
        } else if (arg == "--only" && value) {
            o.only = argv[++k];
        } else if (arg == "--ext-sizes" && value) {
            o.extSizes = parseList(argv[++k]);
        } else if (arg == "--cone-ext-max" && value) {
            o.coneExtMax = std::atoi(argv[++k]);
        } else if (arg == "--gain-size" && value) {
            o.gainSize = std::atoi(argv[++k]);
        } else if (arg == "--ext-map" && value) {
            o.extMap = argv[++k];
            if (!loadHeightfield(fmt::format("gen:{}:8x8:1", o.extMap)).ok()) {
                std::fprintf(stderr, "bench_safety: error: unknown generator '%s'\n",
                             o.extMap.c_str());
                return 1;
            }
        } else if (arg == "--earth" && value) {
            o.earth = argv[++k];
        } else if (arg == "--out" && value) {
            o.out = argv[++k];
        } else {
            std::fprintf(stderr, "bench_safety: error: bad or incomplete option '%s'\n%s",
                         arg.c_str(), kHelp);
            return 1;
        }
    }
    if (o.repeats == 0) o.repeats = o.quick ? 1 : 3;
    if (o.quick) o.sizes = {64, 128}, o.compare = {64, 128}, o.extSizes = {64, 128}, o.gainSize = 128;
    return 0;
}

double seconds(const std::function<void()>& fn) { return bestSeconds(1, fn); }

std::shared_ptr<const Surface> generatedSurface(const std::string& generator, int size) {
    auto hf = loadHeightfield(fmt::format("gen:{}:{}x{}:1", generator, size, size));
    RELIEF_CHECK(hf.ok());
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(*hf)),
                                           0.1f * float(size), EdgeMode::Clamp);
}

std::shared_ptr<const Surface> fbmSurface(int size) { return generatedSurface("fbm", size); }

double meanRadius(const safety::DistanceMap& m) {
    double sum = 0;
    for (uint16_t r : m.r) sum += r;
    return sum / double(m.r.size());
}

// (1) precomputation.
std::string precomputeTable(const Options& o, int threads) {
    std::string t = fmt::format(
        "| map | SD (s) | CC slope scan (s) | SD + CC (s) | SD φ−45° (s) | mean r | mean r "
        "φ−45° | N-buffer lookups |\n|---|---|---|---|---|---|---|---|\n");
    std::vector<std::pair<std::string, std::shared_ptr<const Surface>>> maps;
    for (int n : o.sizes) maps.push_back({fmt::format("fbm {}²", n), fbmSurface(n)});
    if (!o.earth.empty()) {
        auto hf = loadHeightfield(o.earth);
        if (hf.ok()) {
            const int w = hf->width, h = hf->height;
            maps.push_back({fmt::format("earth {}×{}", w, h),
                            std::make_shared<const Surface>(
                                std::make_shared<const Heightfield>(std::move(*hf)),
                                0.01f * float(std::max(w, h)), EdgeMode::Repeat)});
        } else {
            std::fprintf(stderr, "bench_safety: %s\n", hf.error().message.c_str());
        }
    }
    for (auto& [label, s] : maps) {
        std::fprintf(stderr, "bench_safety: precompute %s\n", label.c_str());
        std::fflush(stderr);
        safety::BuildOptions all, phi;
        phi.phiMaxDeg = -45.0;
        safety::DistanceMap sd, sdPhi;
        const double tSd = seconds([&] { sd = safety::buildDistanceMap(*s, all); });
        const double tCc = seconds([&] { safety::buildConeMap(*s, sd, all); });
        // φ_max builds scan wide wedges (mean r ≈ 50) with trigonometry per steep triangle.
        const bool withPhi = s->width() <= 512;
        const double tPhi =
            withPhi ? seconds([&] { sdPhi = safety::buildDistanceMap(*s, phi); }) : -1.0;
        t += fmt::format("| {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | 2 per "
                         "abscissa |\n",
                         label, tSd, tCc, tSd + tCc, tPhi, meanRadius(sd),
                         withPhi ? meanRadius(sdPhi) : -1.0);
    }
    return t + fmt::format("\n{} threads. SD = safety distances, 4 classes; CC = the slanted "
                           "planes given SD's radii (the full CC build is SD + CC).\n",
                           threads);
}

struct Method {
    std::string label, technique;
    std::vector<std::pair<std::string, double>> params;
    int maxSize = 1 << 30;  // larger maps skipped (build time)
};

std::vector<Method> methods(bool quick) {
    std::vector<Method> m = {{"NA (exact)", "exact", {}}};
    for (int n : quick ? std::vector<int>{16} : std::vector<int>{16, 32, 64})
        m.push_back({fmt::format("LS {}", n), "linear", {{"max-steps", n}}});
    if (findTechnique("relaxed-cone"))
        for (int n : quick ? std::vector<int>{15} : std::vector<int>{8, 15, 35})
            m.push_back({fmt::format("RC {}", n), "relaxed-cone",
                         {{"max-steps", n}, {"variant", 1}}, 512});  // its build: slow at 1024²
    for (const char* t : {"safety-sd", "safety-cc"}) {
        const std::string shortName = t == std::string("safety-sd") ? "SD" : "CC";
        m.push_back({shortName, t, {}});
        m.push_back({shortName + " iso", t, {{"isotropic", 1}}});
        // φ_max builds scan wedges of mean radius ≈ 50 with trigonometry per steep triangle:
        // minutes at 1024² on 2 threads (see the precomputation table), so 256² and 512² only.
        m.push_back({shortName + " φ−45°", t, {{"phi-max", -45}}, 512});
        m.push_back({shortName + " d>0", t, {{"positive-distance", 1}}});
        m.push_back({shortName + " lin", t, {{"view-dependent", 1}}});
    }
    return m;
}

struct Timed {
    double seconds = 0;
    std::vector<Hit> hits;
};

Timed traceAll(const Tracer& tracer, const std::vector<Ray>& rays, int repeats) {
    Timed r;
    r.hits.resize(rays.size());
    const std::span<const Ray> all(rays);
    r.seconds = bestSeconds(repeats, [&] {
        forEachTile(rays.size(), [&](size_t first, size_t n) {
            tracer.traceBatch(all.subspan(first, n), std::span(r.hits).subspan(first, n));
        });
    });
    return r;
}

ErrorStats errors(const std::vector<Hit>& hits, const std::vector<Hit>& ref, int w, int h) {
    Image<Hit> a(w, h), b(w, h);
    a.pixels = hits;
    b.pixels = ref;
    return compareHits(a, b);
}

// (2) + (3).
std::string comparisonTables(const Options& o, std::string& embreeTable) {
    const int w = o.quick ? 320 : 1280, h = o.quick ? 256 : 1024;
    const std::vector<int>& sizes = o.compare;
    const std::vector<Method> ms = methods(o.quick);
    OrbitView view;
    view.elevationDeg = 52.7f;
    view.azimuthDeg = 30.0f;
    view.distance = 0.6f;  // the relief covers the screen, as in the paper's Fig. 29
    view.fovDeg = 45.0f;
    std::string t = "| method |";
    for (int n : sizes) t += fmt::format(" {}² ms | {}² wrong % | {}² steps |", n, n, n);
    t += "\n|---|";
    for (size_t k = 0; k < sizes.size(); ++k) t += "---|---|---|";
    t += "\n";
    std::vector<std::vector<std::string>> cells(ms.size());
    embreeTable = "| map | rays | CC Mrays/s | SD Mrays/s | NA Mrays/s | Embree 1 Mrays/s | "
                  "Embree 16 Mrays/s | CC / Embree 1 | CC / Embree 16 |\n"
                  "|---|---|---|---|---|---|---|---|---|\n";
    for (int n : sizes) {
        auto s = fbmSurface(n);
        const Camera camera(view, *s, w, h);
        const std::vector<Ray> rays = tiledPrimaryRays(camera);
        std::fprintf(stderr, "bench_safety: %d² (%zu rays)\n", n, rays.size());
        size_t outside = 0;
        const double tanPhi = safety::tanPhiMax(-45.0);
        for (const Ray& r : rays) outside += !safety::rayWithinPhiMax(r.direction, tanPhi);
        std::vector<Hit> reference;
        double mrays[3] = {0, 0, 0};  // CC, SD, NA
        for (size_t m = 0; m < ms.size(); ++m) {
            if (n > ms[m].maxSize) {
                cells[m].push_back("— | — | —");
                continue;
            }
            std::fprintf(stderr, "bench_safety:   %s\n", ms[m].label.c_str());
            auto tracer = createTracer(ms[m].technique, s, ms[m].params);
            RELIEF_CHECK(tracer.ok());
            const Timed r = traceAll(**tracer, rays, o.repeats);
            if (m == 0) reference = r.hits;
            const ErrorStats e = errors(r.hits, reference, w, h);
            cells[m].push_back(fmt::format("{:.1f} | {:.3f} | {:.1f}", 1e3 * r.seconds,
                                           100.0 * e.wrongRate(), e.steps.mean));
            const double rate = double(rays.size()) / r.seconds / 1e6;
            if (ms[m].label == "CC") mrays[0] = rate;
            if (ms[m].label == "SD") mrays[1] = rate;
            if (m == 0) mrays[2] = rate;
        }
        auto scene = EmbreeScene::create(*s);
        RELIEF_CHECK(scene.ok());
        const std::span<const Ray> all(rays);
        std::vector<Hit> hits(rays.size());
        const double t1 = bestSeconds(o.repeats, [&] {
            forEachTile(rays.size(), [&](size_t first, size_t k) {
                (*scene)->intersect1(all.subspan(first, k), std::span(hits).subspan(first, k));
            });
        });
        const double t16 = bestSeconds(o.repeats, [&] {
            forEachTile(rays.size(), [&](size_t first, size_t k) {
                (*scene)->intersect16(all.subspan(first, k), std::span(hits).subspan(first, k));
            });
        });
        const double e1 = double(rays.size()) / t1 / 1e6, e16 = double(rays.size()) / t16 / 1e6;
        embreeTable += fmt::format("| fbm {}² | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | "
                                   "{:.2f} | {:.2f} |\n",
                                   n, rays.size(), mrays[0], mrays[1], mrays[2], e1, e16,
                                   mrays[0] / e1, mrays[0] / e16);
        std::fprintf(stderr, "bench_safety: %d²: %.1f%% of the rays outside φ_max = −45°\n", n,
                     100.0 * double(outside) / double(rays.size()));
        if (n == sizes.back())
            embreeTable += fmt::format("\nRays outside φ_max = −45° (exact walk) at {}²: {:.1f}%\n",
                                       n, 100.0 * double(outside) / double(rays.size()));
    }
    for (size_t m = 0; m < ms.size(); ++m) {
        t += "| " + ms[m].label + " |";
        for (const std::string& c : cells[m]) t += " " + c + " |";
        t += "\n";
    }
    return t + fmt::format("\n{}×{} primary rays, orbit view elevation {}°, azimuth {}°, "
                           "distance {} diagonals, fov {}°; fbm, depth 0.1·N, clamp. Wrong = "
                           "hit/miss differs or |Δt| > 0.5 texel vs `exact`.\n",
                           w, h, view.elevationDeg, view.azimuthDeg, view.distance, view.fovDeg);
}

// (4) Exterior rays (§6.2): build times (wall and process CPU seconds, the machine is shared)
// and the rendering gain of the exterior maps over the all-ray maps per elevation.
struct Clocked {
    double wall = 0, cpu = 0;
};

Clocked clocked(const std::function<void()>& fn) {
    const std::clock_t c0 = std::clock();
    Clocked t;
    t.wall = seconds(fn);
    t.cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
    return t;
}

struct GainMaps {
    std::vector<std::pair<std::string, TechniqueMaps>> variants;  // label → baked maps
};

std::string exteriorBuildTable(const Options& o, GainMaps& gain) {
    std::string t = "| map | cyl_all (s) | cyl_ext wall (s) | cyl_ext CPU (s) | cone_ext wall (s) | "
                    "cone_ext CPU (s) | mean r all | mean r ext | load before / after |\n"
                    "|---|---|---|---|---|---|---|---|---|\n";
    for (int n : o.extSizes) {
        std::fprintf(stderr, "bench_safety: exterior build %d²\n", n);
        std::fflush(stderr);
        auto s = generatedSurface(o.extMap, n);
        safety::BuildOptions all, ext, extSlope;
        ext.exterior = extSlope.exterior = extSlope.exteriorSlope = true;
        const std::string loadBefore = loadAverage();
        safety::DistanceMap sdAll, sdExt;
        safety::CylinderConeMap ccExt;
        const Clocked tAll = clocked([&] { sdAll = safety::buildDistanceMap(*s, all); });
        const Clocked tExt = clocked([&] { sdExt = safety::buildDistanceMap(*s, ext); });
        const bool cone = n <= o.coneExtMax;
        const Clocked tCone =
            cone ? clocked([&] { ccExt = safety::buildConeMap(*s, sdExt, extSlope); }) : Clocked{-1, -1};
        t += fmt::format("| {} {}² | {:.2f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.2f} | {:.2f} | "
                         "{} / {} |\n",
                         o.extMap, n, tAll.wall, tExt.wall, tExt.cpu, tCone.wall, tCone.cpu,
                         meanRadius(sdAll), meanRadius(sdExt), loadBefore, loadAverage());
        if (n != o.gainSize) continue;
        gain.variants = {
            {"SD", safety::distanceMapToArrays("safety-sd", sdAll, all)},
            {"SD ext", safety::distanceMapToArrays("safety-sd", sdExt, ext)},
            {"CC", safety::coneMapToArrays("safety-cc", safety::buildConeMap(*s, sdAll, all), all)},
            {"CC cyl_ext", safety::coneMapToArrays("safety-cc", safety::buildConeMap(*s, sdExt, ext), ext)}};
        if (cone) gain.variants.push_back({"CC cone_ext", safety::coneMapToArrays("safety-cc", ccExt, extSlope)});
    }
    return t + "\ncyl_ext = exterior safety distances (4 classes); cone_ext = the slanted planes "
               "over exterior-limiting triangles given cyl_ext's radii (the full cone_ext build "
               "is cyl_ext + cone_ext); −1 = not run. CPU = process CPU seconds (all threads).\n";
}

std::string exteriorGainTable(const Options& o, const GainMaps& gain) {
    if (gain.variants.empty()) return "(no gain table: --gain-size is not among --ext-sizes)\n";
    const int w = o.quick ? 320 : 1280, h = o.quick ? 256 : 1024;
    auto s = generatedSurface(o.extMap, o.gainSize);
    std::string t = "| elevation |";
    for (const auto& v : gain.variants) t += fmt::format(" {} ms | {} steps |", v.first, v.first);
    t += " wrong (ext) |\n|---|";
    for (size_t k = 0; k < gain.variants.size(); ++k) t += "---|---|";
    t += "---|\n";
    for (float elevation : {2.9f, 15.3f, 27.8f, 40.2f, 52.7f, 65.1f, 77.6f, 90.0f}) {
        std::fprintf(stderr, "bench_safety: exterior gain, elevation %.1f\n", elevation);
        OrbitView view;
        view.elevationDeg = elevation;
        view.azimuthDeg = 30.0f;
        view.distance = 0.6f;
        view.fovDeg = 45.0f;
        const Camera camera(view, *s, w, h);
        const std::vector<Ray> rays = tiledPrimaryRays(camera);
        auto exact = createTracer("exact", s, {});
        RELIEF_CHECK(exact.ok());
        const std::vector<Hit> reference = traceAll(**exact, rays, 1).hits;
        t += fmt::format("| {}° |", elevation);
        size_t wrong = 0;
        for (const auto& [label, maps] : gain.variants) {
            const TechniqueInfo& info = *findTechnique(maps.technique);
            auto params = resolveParams(info, {});
            RELIEF_CHECK(params.ok());
            auto tracer = info.create(TechniqueInput{s, *params, &maps});
            RELIEF_CHECK(tracer.ok());
            const Timed r = traceAll(**tracer, rays, o.repeats);
            const ErrorStats e = errors(r.hits, reference, w, h);
            if (label.find("ext") != std::string::npos) wrong += size_t(e.wrongRate() * rays.size() + 0.5);
            t += fmt::format(" {:.1f} | {:.2f} |", 1e3 * r.seconds, e.steps.mean);
        }
        t += fmt::format(" {} |\n", wrong);
    }
    return t + fmt::format("\n{}×{} primary rays, {} {}², depth 0.1·N, clamp, orbit view azimuth "
                           "30°, distance 0.6 diagonals (camera outside the box), fov 45°; ms = "
                           "wall time of all rays, best of {}; steps = mean per pixel; wrong = "
                           "pixels of the exterior maps differing from `exact` (hit/miss or "
                           "|Δt| > 0.5).\n",
                           w, h, o.extMap, o.gainSize, o.repeats);
}

int run(const Options& o) {
    const ThreadLimit limit(o.threads);
    const int threads = ThreadLimit::current();
    std::string report = fmt::format("Machine: {}; {} threads; load average at start {}; {}.\n\n",
                                     machineDescription(), threads, loadAverage(), todayUtc());
    if (o.only == "exterior") {
        GainMaps gain;
        report += "### Exterior rays: precomputation\n\n" + exteriorBuildTable(o, gain);
        report += "\n### Exterior rays: rendering gain per elevation\n\n" + exteriorGainTable(o, gain);
    }
    if (o.only != "compare" && o.only != "exterior")
        report += "### Precomputation\n\n" + precomputeTable(o, threads);
    if (o.only != "precompute" && o.only != "exterior") {
        std::string embree;
        report += "\n### Fig. 29 / Table 1 on this CPU\n\n" + comparisonTables(o, embree);
        report += "\n### Throughput against Embree (same rays, same run)\n\n" + embree;
    }
    report += fmt::format("\nLoad average at the end: {}.\n", loadAverage());
    std::fputs(report.c_str(), stdout);
    if (!o.out.empty()) {
        std::FILE* f = std::fopen(o.out.c_str(), "w");
        if (!f) return 2;
        std::fputs(report.c_str(), f);
        std::fclose(f);
    }
    return 0;
}

}  // namespace
}  // namespace relief

int main(int argc, char** argv) {
    relief::Options o;
    if (const int rc = relief::parseOptions(argc, argv, o); rc != 0) return rc < 0 ? 0 : rc;
    return relief::run(o);
}
