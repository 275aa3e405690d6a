// relief_isa_bench: the CPU tracers' speed per ISA (core/isa.h), side by side in one process on
// the same rays: for each row and view, the ISAs take turns (baseline, sse4, avx2, baseline, ...)
// `repeats` times and the best time of each counts, so machine load hits them alike; beside wall
// time, the process CPU time of the trace (all threads), which time slices lost to other
// processes on a shared machine do not inflate. The hits of
// every ISA are compared bit for bit with the baseline's (a difference is exit 4).
// Usage: relief_isa_bench [--heightfield SRC] [--size WxH] [--threads N] [--repeats N]
//                         [--elevations A,B,..] [--techniques a,b,..] [--depth-ratio R]
// Prints a Markdown table (docs/benchmarks-isa.md).
#include <relief/core/isa.h>
#include <relief/core/parallel.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/camera.h>
#include <relief/techniques/registry.h>

#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace relief {
namespace {

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = text.find(',', start);
        const size_t end = comma == std::string::npos ? text.size() : comma;
        if (end > start) out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

double processCpuSeconds() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

bool sameBits(const Hit& a, const Hit& b) {
    return a.hit == b.hit && std::memcmp(&a.t, &b.t, sizeof a.t) == 0 &&
           std::memcmp(&a.position, &b.position, sizeof a.position) == 0 && a.steps == b.steps &&
           a.fetches == b.fetches;
}

int run(int argc, char** argv) {
    std::string source = "gen:fbm:1024x1024:1", techniques = "exact,quadtree,maxmip,cone,safety-cc,qdm";
    std::string elevations = "15.3,40.2,65.1";
    int width = 640, height = 512, threads = 2, repeats = 5;
    float depthRatio = 0.1f;
    for (int k = 1; k + 1 < argc; k += 2) {
        const std::string key = argv[k], value = argv[k + 1];
        if (key == "--heightfield") source = value;
        else if (key == "--size" && std::sscanf(value.c_str(), "%dx%d", &width, &height) == 2) {}
        else if (key == "--threads") threads = std::atoi(value.c_str());
        else if (key == "--repeats") repeats = std::max(1, std::atoi(value.c_str()));
        else if (key == "--elevations") elevations = value;
        else if (key == "--techniques") techniques = value;
        else if (key == "--depth-ratio") depthRatio = std::strtof(value.c_str(), nullptr);
        else {
            std::fprintf(stderr, "relief_isa_bench: unknown option or value '%s %s'\n", key.c_str(),
                         value.c_str());
            return 1;
        }
    }
    if (argc % 2 == 0) {
        std::fprintf(stderr, "relief_isa_bench: option '%s' lacks its value\n", argv[argc - 1]);
        return 1;
    }
    ThreadLimit limit(threads);
    auto hf = loadHeightfield(source);
    if (!hf) {
        std::fprintf(stderr, "relief_isa_bench: %s\n", hf.error().message.c_str());
        return 1;
    }
    auto heightfield = std::make_shared<const Heightfield>(std::move(*hf));
    auto surface = std::make_shared<const Surface>(
        heightfield, depthRatio * float(std::max(heightfield->width, heightfield->height)),
        EdgeMode::Clamp);
    std::vector<Isa> isas;
    for (Isa isa : kAllIsas)
        if (isaSupported(isa)) isas.push_back(isa);

    std::printf("map %s, depth ratio %g, clamp; %dx%d primary rays per view (azimuth 30, distance "
                "1.2); %d threads; best of %d interleaved runs per ISA\n\n",
                source.c_str(), depthRatio, width, height, threads, repeats);
    std::printf("| technique | elevation |");
    for (Isa isa : isas) std::printf(" %s Mrays/s |", std::string(toString(isa)).c_str());
    for (size_t i = 1; i < isas.size(); ++i)
        std::printf(" %s / baseline (wall) | (CPU) |", std::string(toString(isas[i])).c_str());
    std::printf("\n|---|---|");
    for (size_t i = 0; i + 2 < 3 * isas.size(); ++i) std::printf("---|");
    std::printf("\n");

    int status = 0;
    for (const std::string& name : splitList(techniques)) {
        auto tracer = createTracer(name, surface);
        if (!tracer) {
            std::fprintf(stderr, "relief_isa_bench: %s\n", tracer.error().message.c_str());
            return 1;
        }
        std::vector<double> logRatio(isas.size(), 0.0), logCpuRatio(isas.size(), 0.0);
        const std::vector<std::string> views = splitList(elevations);
        for (const std::string& elevation : views) {
            OrbitView view;
            view.elevationDeg = std::strtof(elevation.c_str(), nullptr);
            const std::vector<Ray> rays = primaryRays(Camera(view, *surface, width, height));
            std::vector<std::vector<Hit>> hits(isas.size(), std::vector<Hit>(rays.size()));
            std::vector<double> best(isas.size(), 1e300), bestCpu(isas.size(), 1e300);
            for (int r = 0; r < repeats; ++r)
                for (size_t i = 0; i < isas.size(); ++i) {
                    IsaOverride use(isas[i]);
                    const double cpuStart = processCpuSeconds();
                    const auto start = std::chrono::steady_clock::now();
                    traceAll(**tracer, rays, hits[i]);
                    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
                    best[i] = std::min(best[i], took.count());
                    bestCpu[i] = std::min(bestCpu[i], processCpuSeconds() - cpuStart);
                }
            for (size_t i = 1; i < isas.size(); ++i)
                for (size_t k = 0; k < rays.size(); ++k)
                    if (!sameBits(hits[0][k], hits[i][k])) {
                        std::fprintf(stderr, "relief_isa_bench: %s differs between baseline and %s "
                                     "at ray %zu\n", name.c_str(),
                                     std::string(toString(isas[i])).c_str(), k);
                        status = 4;
                        break;
                    }
            std::printf("| %s | %s° |", name.c_str(), elevation.c_str());
            for (size_t i = 0; i < isas.size(); ++i)
                std::printf(" %.2f |", double(rays.size()) / best[i] / 1e6);
            for (size_t i = 1; i < isas.size(); ++i) {
                std::printf(" %.2f× | %.2f× |", best[0] / best[i], bestCpu[0] / bestCpu[i]);
                logRatio[i] += std::log(best[0] / best[i]) / double(views.size());
                logCpuRatio[i] += std::log(bestCpu[0] / bestCpu[i]) / double(views.size());
            }
            std::printf("\n");
        }
        std::printf("| **%s** | geomean |", name.c_str());
        for (size_t i = 0; i < isas.size(); ++i) std::printf(" |");
        for (size_t i = 1; i < isas.size(); ++i)
            std::printf(" **%.2f×** | **%.2f×** |", std::exp(logRatio[i]), std::exp(logCpuRatio[i]));
        std::printf("\n");
        std::fflush(stdout);
    }
    return status;
}

}  // namespace
}  // namespace relief

int main(int argc, char** argv) { return relief::run(argc, argv); }
