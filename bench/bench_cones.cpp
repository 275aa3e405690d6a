// bench_cones: cone and relaxed-cone maps (safe and faithful builds): build times, error vs
// iteration cap, mean steps vs elevation, and throughput against `exact` and Embree in the same
// run (DESIGN §8). Writes a markdown report (--out, default stdout only).
//   bench_cones [--quick] [--threads N] [--out FILE]
#include "bench_common.h"

#include <relief/core/generators.h>
#include <relief/embree/embree_scene.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/compare.h>
#include <relief/techniques/cone/cone_common.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <fstream>

using namespace relief;

namespace {

struct Config {
    const char* label;
    const char* technique;
    double variant;
};
constexpr Config kConfigs[] = {{"cone safe", "cone", 0},
                               {"cone faithful", "cone", 1},
                               {"relaxed safe", "relaxed-cone", 0},
                               {"relaxed faithful", "relaxed-cone", 1}};

std::shared_ptr<const Surface> surfaceOf(const Heightfield& hf) {
    auto shared = std::make_shared<const Heightfield>(hf);
    return std::make_shared<const Surface>(shared, 0.1f * float(std::max(hf.width, hf.height)),
                                           EdgeMode::Clamp);
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

std::string buildTable(const std::vector<int>& sizes) {
    std::string out = "| size | cone safe (= relaxed safe) | cone faithful | relaxed faithful |\n"
                      "|---|---|---|---|\n";
    for (int n : sizes) {
        const auto s = surfaceOf(*generateHeightfield("fbm", n, n, 1));
        out += fmt::format("| {}² |", n);
        for (ConeKind kind : {ConeKind::SafeStrict, ConeKind::FaithfulStrict,
                              ConeKind::FaithfulRelaxed}) {
            const double sec = bench::bestSeconds(1, [&] { (void)buildCones(*s, kind); });
            out += fmt::format(" {:.2f} s |", sec);
            std::fprintf(stderr, "build %d kind %d: %.2f s\n", n, int(kind), sec);
        }
        out += "\n";
    }
    return out;
}

std::unique_ptr<Tracer> makeTracer(const Surface& s, std::shared_ptr<const Surface> sp,
                                   const Config& c, double cap, const TechniqueMaps& maps) {
    const TechniqueInfo& info = *findTechnique(c.technique);
    std::vector<std::pair<std::string, double>> params{{"variant", c.variant}};
    if (cap > 0) params.push_back({"max-steps", cap});
    auto values = resolveParams(info, params);
    return std::move(*info.create(TechniqueInput{sp, *values, &maps}));
}

TechniqueMaps mapsFor(std::shared_ptr<const Surface> sp, const Config& c) {
    const TechniqueInfo& info = *findTechnique(c.technique);
    auto values = resolveParams(info, {{"variant", c.variant}});
    return std::move(*info.buildMaps(TechniqueInput{sp, *values}));
}

// Error vs cap (mean |dt|, wrong %) over the 8 standard elevations, and mean steps vs elevation.
std::string qualityTables(const char* name, std::shared_ptr<const Surface> sp, int px) {
    const Surface& s = *sp;
    auto exact = createTracer("exact", sp);
    std::vector<std::vector<Ray>> rays;
    std::vector<Image<Hit>> refs;
    for (float el : kStandardElevations) {
        const Camera cam(OrbitView{el, 30.0f, 1.2f, 45.0f}, s, px, px);
        rays.push_back(primaryRays(cam));
        refs.push_back(traceImage(**exact, rays.back(), px, px));
    }
    std::string caps = fmt::format("\n**{}** — mean |Δt| (texels) / wrong-hit % over the 8 "
                                   "elevations, by max-steps\n\n| technique |", name);
    for (int cap : kStandardCaps) caps += fmt::format(" {} |", cap);
    caps += "\n|---|";
    for (size_t k = 0; k < std::size(kStandardCaps); ++k) caps += "---|";
    caps += "\n";
    std::string steps = fmt::format("\n**{}** — mean steps per pixel at the default caps, by "
                                    "elevation\n\n| technique |", name);
    for (float el : kStandardElevations) steps += fmt::format(" {}° |", el);
    steps += "\n|---|";
    for (size_t k = 0; k < std::size(kStandardElevations); ++k) steps += "---|";
    steps += "\n";
    for (const Config& c : kConfigs) {
        const TechniqueMaps maps = mapsFor(sp, c);
        caps += fmt::format("| {} |", c.label);
        for (int cap : kStandardCaps) {
            auto tracer = makeTracer(s, sp, c, cap, maps);
            double err = 0, wrong = 0;
            for (size_t e = 0; e < rays.size(); ++e) {
                const ErrorStats st = compareHits(traceImage(*tracer, rays[e], px, px), refs[e]);
                err += st.error.mean / double(rays.size());
                wrong += 100.0 * st.wrongRate() / double(rays.size());
            }
            caps += fmt::format(" {:.3g} / {:.2g} |", err, wrong);
        }
        caps += "\n";
        steps += fmt::format("| {} |", c.label);
        auto tracer = makeTracer(s, sp, c, 0, maps);
        for (size_t e = 0; e < rays.size(); ++e) {
            const ErrorStats st = compareHits(traceImage(*tracer, rays[e], px, px), refs[e]);
            steps += fmt::format(" {:.1f} |", st.steps.mean);
        }
        steps += "\n";
        std::fprintf(stderr, "quality %s %s done\n", name, c.label);
    }
    return caps + steps;
}

std::string throughputTable(std::shared_ptr<const Surface> sp, int px) {
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
        auto tracer = makeTracer(s, sp, c, 0, mapsFor(sp, c));
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
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    int threads = 2;
    std::string outPath;
    for (int k = 1; k < argc; ++k) {
        if (!std::strcmp(argv[k], "--quick")) quick = true;
        else if (!std::strcmp(argv[k], "--threads") && k + 1 < argc) threads = std::atoi(argv[++k]);
        else if (!std::strcmp(argv[k], "--out") && k + 1 < argc) outPath = argv[++k];
        else {
            std::fprintf(stderr, "usage: bench_cones [--quick] [--threads N] [--out FILE]\n");
            return 1;
        }
    }
    const ThreadLimit limit(threads);
    const int n = quick ? 256 : 1024, px = quick ? 128 : 256;
    std::string report = fmt::format("Machine: {}; threads: {}; load: {}; date: {}\n\n",
                                     bench::machineDescription(), threads, bench::loadAverage(),
                                     bench::todayUtc());
    report += "### Build time (fbm, wall seconds)\n\n" +
              buildTable(quick ? std::vector<int>{256, 512} : std::vector<int>{256, 512, 1024, 2048});
    const auto fbm = surfaceOf(*generateHeightfield("fbm", n, n, 1));
    report += fmt::format("\n### Quality ({}×{} px images, depth 0.1·size)\n", px, px);
    report += qualityTables(fmt::format("fbm {}²", n).c_str(), fbm, px);
    auto colorado = loadHeightfield("/work/shared/data/colorado-elevation-400.png");
    if (colorado.ok()) report += qualityTables("colorado 400²", surfaceOf(*colorado), px);
    report += fmt::format("\n### Throughput (fbm {}², 40.2°, {}² px, same run)\n\n", n, 2 * px);
    report += throughputTable(fbm, 2 * px);
    std::printf("%s", report.c_str());
    if (!outPath.empty()) std::ofstream(outPath) << report;
    return 0;
}
