// bench_qdm: quadratic displacement maps against safe cone step mapping, the experiments of
// Kiglics et al. 2023 §5 on the CPU: mean |Δt| along the ray vs iteration cap (their Fig. 9),
// mean steps vs elevation (Fig. 10), time per frame difference and ratio (Table 1, Fig. 11),
// averaged over the built-in and real maps, plus build times. Writes a markdown report.
//   bench_qdm [--quick] [--threads N] [--big] [--out FILE]
#include "bench_common.h"

#include <relief/core/generators.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/compare.h>
#include <relief/techniques/qdm/qdm.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>

using namespace relief;

namespace {

constexpr const char* kTechniques[] = {"qdm", "cone"};
constexpr size_t kElevations = std::size(kStandardElevations);
constexpr size_t kCaps = std::size(kStandardCaps);
constexpr int kImageW = 320, kImageH = 256;

struct MapCase {
    std::string name;
    std::shared_ptr<const Surface> surface;
};

std::shared_ptr<const Surface> surfaceOf(const Heightfield& hf) {
    auto shared = std::make_shared<const Heightfield>(hf);
    return std::make_shared<const Surface>(shared, 0.1f * float(std::max(hf.width, hf.height)),
                                           EdgeMode::Clamp);
}

std::vector<MapCase> mapCases(int n) {
    std::vector<MapCase> cases;
    for (const char* g : {"sine", "peaks6", "fbm", "terraces", "walls"})
        cases.push_back({fmt::format("{} {}²", g, n), surfaceOf(*generateHeightfield(g, n, n, 1))});
    for (const char* file : {"colorado-elevation-400.png", "finland-topography-400-16bit.png"}) {
        auto hf = loadHeightfield(std::string("/work/shared/data/") + file);
        if (hf.ok()) cases.push_back({file, surfaceOf(*hf)});
        else std::fprintf(stderr, "skipping %s: %s\n", file, hf.error().message.c_str());
    }
    return cases;
}

Image<Hit> traceImage(const Tracer& tracer, const std::vector<Ray>& rays) {
    Image<Hit> image(kImageW, kImageH);
    parallelRanges(int64_t(kImageH), 4, [&](int64_t begin, int64_t end) {
        const size_t first = size_t(begin) * kImageW, count = size_t(end - begin) * kImageW;
        tracer.traceBatch(std::span(rays).subspan(first, count),
                          std::span(image.pixels).subspan(first, count));
    });
    return image;
}

std::unique_ptr<Tracer> makeTracer(std::shared_ptr<const Surface> sp, const char* technique,
                                   int cap, const TechniqueMaps& maps) {
    const TechniqueInfo& info = *findTechnique(technique);
    std::vector<std::pair<std::string, double>> params;
    if (cap > 0) params.push_back({"max-steps", cap});
    return std::move(*info.create(TechniqueInput{sp, *resolveParams(info, params), &maps}));
}

// Sums over maps, per technique, elevation and cap (index kCaps = the default cap).
struct Sums {
    std::array<std::array<std::array<double, kCaps + 1>, kElevations>, 2> error{}, wrong{},
        steps{}, ms{};
    int maps = 0;
};

struct BuildRow {
    std::string map;
    std::array<double, 2> seconds;
};

void measureMap(const MapCase& m, Sums& sums, std::vector<BuildRow>& builds) {
    std::array<TechniqueMaps, 2> maps;
    BuildRow row{m.name, {}};
    for (size_t k = 0; k < 2; ++k) {
        const TechniqueInfo& info = *findTechnique(kTechniques[k]);
        const ParamValues params = *resolveParams(info, {});
        row.seconds[k] = bench::bestSeconds(
            1, [&] { maps[k] = std::move(*info.buildMaps(TechniqueInput{m.surface, params})); });
    }
    builds.push_back(row);
    std::fprintf(stderr, "%s: build qdm %.2f s, cone %.2f s\n", m.name.c_str(), row.seconds[0],
                 row.seconds[1]);
    auto exact = createTracer("exact", m.surface);
    for (size_t e = 0; e < kElevations; ++e) {
        const Camera cam(OrbitView{kStandardElevations[e], 30.0f, 1.2f, 45.0f}, *m.surface,
                         kImageW, kImageH);
        const std::vector<Ray> rays = primaryRays(cam);
        const Image<Hit> ref = traceImage(**exact, rays);
        for (size_t k = 0; k < 2; ++k)
            for (size_t c = 0; c <= kCaps; ++c) {
                auto tracer = makeTracer(m.surface, kTechniques[k],
                                         c < kCaps ? kStandardCaps[c] : 0, maps[k]);
                Image<Hit> hits;
                const double sec = bench::bestSeconds(3, [&] { hits = traceImage(*tracer, rays); });
                const ErrorStats st = compareHits(hits, ref);
                sums.error[k][e][c] += st.error.mean;
                sums.wrong[k][e][c] += 100.0 * st.wrongRate();
                sums.steps[k][e][c] += st.steps.mean;
                sums.ms[k][e][c] += 1e3 * sec;
            }
    }
    ++sums.maps;
}

std::string header(const char* first) {
    std::string out = fmt::format("| {} |", first);
    for (int cap : kStandardCaps) out += fmt::format(" {} |", cap);
    out += " default |\n|---|";
    for (size_t c = 0; c <= kCaps; ++c) out += "---|";
    return out + "\n";
}

template <class Cell>
std::string byElevationAndCap(const char* first, Cell&& cell) {
    std::string out = header(first);
    for (size_t e = 0; e < kElevations; ++e) {
        out += fmt::format("| {}° |", kStandardElevations[e]);
        for (size_t c = 0; c <= kCaps; ++c) out += " " + cell(e, c) + " |";
        out += "\n";
    }
    return out;
}

std::string report(const Sums& s, const std::vector<BuildRow>& builds) {
    const double n = double(s.maps);
    std::string out = "### Build time (wall seconds, default parameters)\n\n"
                      "| map | qdm | cone (safe) |\n|---|---|---|\n";
    for (const BuildRow& b : builds)
        out += fmt::format("| {} | {:.2f} | {:.2f} |\n", b.map, b.seconds[0], b.seconds[1]);
    out += "\n### Mean |Δt| along the ray (texels), qdm / cone, by elevation and max-steps "
           "(Fig. 9)\n\n";
    out += byElevationAndCap("elevation", [&](size_t e, size_t c) {
        return fmt::format("{:.3g} / {:.3g}", s.error[0][e][c] / n, s.error[1][e][c] / n);
    });
    out += "\n### Wrong-hit pixels (%), qdm / cone (unconverged rays at a cap stop short)\n\n";
    out += byElevationAndCap("elevation", [&](size_t e, size_t c) {
        return fmt::format("{:.2g} / {:.2g}", s.wrong[0][e][c] / n, s.wrong[1][e][c] / n);
    });
    out += "\n### Mean steps per pixel until termination, default cap (Fig. 10)\n\n"
           "| technique |";
    for (float el : kStandardElevations) out += fmt::format(" {}° |", el);
    out += "\n|---|";
    for (size_t e = 0; e < kElevations; ++e) out += "---|";
    out += "\n";
    for (size_t k = 0; k < 2; ++k) {
        out += fmt::format("| {} |", kTechniques[k]);
        for (size_t e = 0; e < kElevations; ++e)
            out += fmt::format(" {:.1f} |", s.steps[k][e][kCaps] / n);
        out += "\n";
    }
    out += fmt::format("\n### Cone minus qdm time per frame (ms, {}×{} px, mean over maps; "
                       "negative = qdm faster) (Table 1)\n\n", kImageW, kImageH);
    std::array<double, kCaps + 1> totals{};
    out += byElevationAndCap("elevation", [&](size_t e, size_t c) {
        const double d = (s.ms[1][e][c] - s.ms[0][e][c]) / n;
        totals[c] += d;
        return fmt::format("{:+.2f}", d);
    });
    out += "| total |";
    for (double t : totals) out += fmt::format(" {:+.2f} |", t);
    out += "\n\n### Time ratio qdm / cone per frame (Fig. 11; < 1 = qdm faster)\n\n";
    out += byElevationAndCap("elevation", [&](size_t e, size_t c) {
        return fmt::format("{:.2f}", s.ms[0][e][c] / s.ms[1][e][c]);
    });
    out += "\n### Mean time per frame (ms), qdm / cone\n\n";
    out += byElevationAndCap("elevation", [&](size_t e, size_t c) {
        return fmt::format("{:.1f} / {:.1f}", s.ms[0][e][c] / n, s.ms[1][e][c] / n);
    });
    return out;
}

std::string bigBuild() {
    const auto s = surfaceOf(*generateHeightfield("fbm", 4096, 4096, 1));
    const TechniqueInfo& info = *findTechnique("qdm");
    const ParamValues params = *resolveParams(info, {});
    const double sec = bench::bestSeconds(1, [&] { (void)info.buildMaps({s, params}); });
    return fmt::format("\nqdm build, fbm 4096²: {:.1f} s\n", sec);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, big = false;
    int threads = 2;
    std::string outPath;
    for (int k = 1; k < argc; ++k) {
        if (!std::strcmp(argv[k], "--quick")) quick = true;
        else if (!std::strcmp(argv[k], "--big")) big = true;
        else if (!std::strcmp(argv[k], "--threads") && k + 1 < argc) threads = std::atoi(argv[++k]);
        else if (!std::strcmp(argv[k], "--out") && k + 1 < argc) outPath = argv[++k];
        else {
            std::fprintf(stderr, "usage: bench_qdm [--quick] [--big] [--threads N] [--out FILE]\n");
            return 1;
        }
    }
    const ThreadLimit limit(threads);
    std::string text = fmt::format("Machine: {}; threads: {}; load at start: {}; date: {}\n\n",
                                   bench::machineDescription(), threads, bench::loadAverage(),
                                   bench::todayUtc());
    Sums sums;
    std::vector<BuildRow> builds;
    for (const MapCase& m : mapCases(quick ? 256 : 1024)) measureMap(m, sums, builds);
    text += report(sums, builds);
    if (big) text += bigBuild();
    text += fmt::format("\nLoad at end: {}\n", bench::loadAverage());
    std::printf("%s", text.c_str());
    if (!outPath.empty()) std::ofstream(outPath) << text;
    return 0;
}
