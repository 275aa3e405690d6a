// bench_qdm: quadratic displacement maps against safe cone step mapping, the experiments of
// Kiglics et al. 2023 §5 on the CPU: mean |Δt| along the ray vs iteration cap (their Fig. 9),
// mean steps vs elevation (Fig. 10), time per frame difference and ratio (Table 1, Fig. 11),
// averaged over nine maps (five generators, two real DEMs at their native 400², two crops of
// real global relief at the map size), plus build times. Writes a markdown report.
//   bench_qdm [--quick] [--size N] [--image WxH] [--threads N] [--big] [--out FILE]
//   bench_qdm --builds N[,N...] [--threads N] [--out FILE]   qdm build times only (wall, CPU)
//   --gens G[,G...]: only these generators (no real maps), e.g. --builds 512,1024 --gens peaks6,fbm
#include "bench_common.h"

#include <relief/core/generators.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/compare.h>
#include <relief/techniques/qdm/qdm.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sys/resource.h>

using namespace relief;

namespace {

constexpr const char* kTechniques[] = {"qdm", "cone"};
constexpr size_t kElevations = std::size(kStandardElevations);
constexpr size_t kCaps = std::size(kStandardCaps);

struct ImageSize {
    int width = 320, height = 256;
};

struct MapCase {
    std::string name;
    std::shared_ptr<const Surface> surface;
};

std::shared_ptr<const Surface> surfaceOf(const Heightfield& hf) {
    auto shared = std::make_shared<const Heightfield>(hf);
    return std::make_shared<const Surface>(shared, 0.1f * float(std::max(hf.width, hf.height)),
                                           EdgeMode::Clamp);
}

// An n×n window of a larger map with its corner at (x0, y0), renormalized to [0, 1].
Result<Heightfield> crop(const Heightfield& hf, int x0, int y0, int n) {
    if (x0 + n > hf.width || y0 + n > hf.height)
        return makeError(ErrorKind::InvalidInput, "crop {}² at ({}, {}) exceeds {}x{}", n, x0, y0,
                         hf.width, hf.height);
    std::vector<float> raw;
    raw.reserve(size_t(n) * size_t(n));
    for (int j = y0; j < y0 + n; ++j)
        for (int i = x0; i < x0 + n; ++i) raw.push_back(hf.at(i, j));
    if (Status st = normalizeSamples("crop", raw, n, 0.0, 0.0); !st.ok()) return st.error();
    return Heightfield{n, n, std::move(raw)};
}

struct RealMap {
    const char* file;
    int cropX = -1, cropY = -1;  // -1: the whole map at its native size
    const char* label = nullptr;
};
// The two 400² DEMs as they are; the crops (Andes and Pacific coast from the 15 px/° SRTM
// mosaic, Africa and Europe from the 2048×1024 topography) at the requested size.
constexpr RealMap kRealMaps[] = {
    {"colorado-elevation-400.png"},
    {"finland-topography-400-16bit.png"},
    {"earth-srtm-5400x2700.png", 1500, 1100, "srtm andes"},
    {"earth-topology-2048x1024.png", 900, 0, "topology africa-europe"},
};

std::vector<std::string> g_onlyGenerators;  // --gens: empty = all maps

std::vector<MapCase> mapCases(int n) {
    std::vector<MapCase> cases;
    for (const char* g : {"sine", "peaks6", "fbm", "terraces", "walls"})
        if (g_onlyGenerators.empty() || std::find(g_onlyGenerators.begin(), g_onlyGenerators.end(),
                                                  std::string(g)) != g_onlyGenerators.end())
            cases.push_back(
                {fmt::format("{} {}²", g, n), surfaceOf(*generateHeightfield(g, n, n, 1))});
    if (!g_onlyGenerators.empty()) return cases;
    for (const RealMap& real : kRealMaps) {
        auto hf = loadHeightfield(std::string("/work/shared/data/") + real.file);
        if (hf.ok() && real.cropX >= 0) hf = crop(*hf, real.cropX, real.cropY, n);
        if (!hf.ok()) {
            std::fprintf(stderr, "skipping %s: %s\n", real.file, hf.error().message.c_str());
            continue;
        }
        cases.push_back({real.cropX >= 0 ? fmt::format("{} {}²", real.label, n) : real.file,
                         surfaceOf(*hf)});
    }
    return cases;
}

Image<Hit> traceImage(const Tracer& tracer, const std::vector<Ray>& rays, ImageSize size) {
    Image<Hit> image(size.width, size.height);
    const size_t w = size_t(size.width);
    parallelRanges(int64_t(size.height), 4, [&](int64_t begin, int64_t end) {
        const size_t first = size_t(begin) * w, count = size_t(end - begin) * w;
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

void measureMap(const MapCase& m, ImageSize size, Sums& sums, std::vector<BuildRow>& builds) {
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
                         size.width, size.height);
        const std::vector<Ray> rays = primaryRays(cam);
        const Image<Hit> ref = traceImage(**exact, rays, size);
        for (size_t k = 0; k < 2; ++k)
            for (size_t c = 0; c <= kCaps; ++c) {
                auto tracer = makeTracer(m.surface, kTechniques[k],
                                         c < kCaps ? kStandardCaps[c] : 0, maps[k]);
                Image<Hit> hits;
                const double sec =
                    bench::bestSeconds(3, [&] { hits = traceImage(*tracer, rays, size); });
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

std::string report(const Sums& s, const std::vector<BuildRow>& builds, ImageSize size) {
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
                       "positive = qdm faster; the paper labels its Table 1 the other way round) (Table 1)\n\n", size.width, size.height);
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

double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// One qdm build at default parameters: wall and process CPU seconds (user + sys, all threads)
// and the 1-minute load before it (the machine is shared: CPU time shows the work, wall time
// what the contention made of it).
std::string buildRow(const MapCase& m) {
    const TechniqueInfo& info = *findTechnique("qdm");
    const ParamValues params = *resolveParams(info, {});
    const std::string load = bench::loadAverage();
    const double cpu0 = processCpuSeconds();
    const double wall = bench::bestSeconds(1, [&] { (void)info.buildMaps({m.surface, params}); });
    const double cpu = processCpuSeconds() - cpu0;
    std::fprintf(stderr, "%s: qdm build %.2f s wall, %.2f s CPU, load %s\n", m.name.c_str(),
                 wall, cpu, load.c_str());
    return fmt::format("| {} | {:.2f} | {:.2f} | {} |\n", m.name, wall, cpu, load);
}

std::string buildTable(const std::vector<int>& sizes) {
    std::string out = "### qdm build time (default parameters)\n\n"
                      "| map | wall s | CPU s (user+sys) | load before |\n|---|---|---|---|\n";
    for (int n : sizes) {
        std::vector<MapCase> cases = mapCases(n);
        for (const MapCase& m : cases)
            if (m.surface->width() == n || n == sizes.front()) out += buildRow(m);
    }
    return out;
}

std::string bigBuild() {
    std::string out = "\n";
    for (const char* g : {"fbm", "peaks6"}) out += buildRow({fmt::format("{} 4096²", g),
        surfaceOf(*generateHeightfield(g, 4096, 4096, 1))});
    return out;
}

std::vector<int> parseSizes(const char* text) {
    std::vector<int> sizes;
    for (const char* p = text; *p;) {
        char* end = nullptr;
        const long n = std::strtol(p, &end, 10);
        if (end == p || n < 16 || n > 16384) return {};
        sizes.push_back(int(n));
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',') return {};
    }
    return sizes;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, big = false;
    int threads = 2, size = 1024;
    ImageSize image;
    std::vector<int> buildSizes;
    std::string outPath;
    bool ok = true;
    for (int k = 1; k < argc && ok; ++k) {
        if (!std::strcmp(argv[k], "--quick")) quick = true;
        else if (!std::strcmp(argv[k], "--big")) big = true;
        else if (!std::strcmp(argv[k], "--threads") && k + 1 < argc)
            ok = bench::parseInt(argv[++k], threads);
        else if (!std::strcmp(argv[k], "--size") && k + 1 < argc)
            ok = bench::parseInt(argv[++k], size) && size >= 16;
        else if (!std::strcmp(argv[k], "--image") && k + 1 < argc)
            ok = std::sscanf(argv[++k], "%dx%d", &image.width, &image.height) == 2 &&
                 image.width > 0 && image.height > 0;
        else if (!std::strcmp(argv[k], "--builds") && k + 1 < argc)
            ok = !(buildSizes = parseSizes(argv[++k])).empty();
        else if (!std::strcmp(argv[k], "--out") && k + 1 < argc) outPath = argv[++k];
        else if (!std::strcmp(argv[k], "--gens") && k + 1 < argc) {
            for (const char* p = argv[++k]; *p;) {
                const char* end = std::strchr(p, ',');
                g_onlyGenerators.emplace_back(p, end ? size_t(end - p) : std::strlen(p));
                p = end ? end + 1 : p + std::strlen(p);
            }
        } else ok = false;
    }
    if (!ok) {
        std::fprintf(stderr, "usage: bench_qdm [--quick] [--size N] [--image WxH] [--big] "
                             "[--builds N,N...] [--gens G,G...] [--threads N] [--out FILE]\n");
        return 1;
    }
    const ThreadLimit limit(threads);
    std::string text = fmt::format("Machine: {}; threads: {}; load at start: {}; date: {}\n\n",
                                   bench::machineDescription(), threads, bench::loadAverage(),
                                   bench::todayUtc());
    if (!buildSizes.empty()) {
        text += buildTable(buildSizes);
        if (big) text += bigBuild();
    } else {
        Sums sums;
        std::vector<BuildRow> builds;
        for (const MapCase& m : mapCases(quick ? 256 : size)) measureMap(m, image, sums, builds);
        text += fmt::format("Maps: {}² (the two 400² DEMs at their own size); image {}×{} px\n\n",
                            quick ? 256 : size, image.width, image.height);
        text += report(sums, builds, image);
        if (big) text += bigBuild();
    }
    text += fmt::format("\nLoad at end: {}\n", bench::loadAverage());
    std::printf("%s", text.c_str());
    if (!outPath.empty()) std::ofstream(outPath) << text;
    return 0;
}
