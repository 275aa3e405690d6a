#pragma once
// Shared pieces of the benchmarks: primary rays of the orbit camera (render/camera.h) laid out
// so that every 4×4 pixel block is 16 consecutive rays (an Embree packet) and every 16×16 pixel
// tile is 256 consecutive rays (a parallel work item), best-of-N timing, and the machine, date
// and table text that go into docs/benchmarks-*.md (DESIGN §8: peers measured in the same run).
#include <relief/core/parallel.h>
#include <relief/render/camera.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <ctime>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace relief::bench {

// An option value in [0, 4096] (threads, repeats); false if the text is anything else.
inline bool parseInt(const char* text, int& value) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (!end || *end != '\0' || v < 0 || v > 4096) return false;
    value = int(v);
    return true;
}

// The repository's root: the bench executables get no RELIEF_SOURCE_DIR from the build, so this
// header's own path locates data/ and ../shared/data.
#ifndef RELIEF_SOURCE_DIR
inline const std::string kSourceDir = [] {
    std::string here = __FILE__;  // <root>/bench/bench_common.h
    for (int up = 0; up < 2 && here.find('/') != std::string::npos; ++up)
        here = here.substr(0, here.rfind('/'));
    return here.empty() ? std::string(".") : here;
}();
#else
inline const std::string kSourceDir = RELIEF_SOURCE_DIR;
#endif

// The options the benchmark executables share; each bench adds its own (BenchOption).
struct CommonOptions {
    bool quick = false;
    int threads = 0;
    int repeats = 0;  // 0 until parsed: then 3, or 1 with --quick
    std::string out;
    std::string dataDir;
};

// A bench's own option: a flag (`flag` set) or one taking a text value (`value` set).
struct BenchOption {
    const char* name;
    bool* flag = nullptr;
    std::string* value = nullptr;
};

// Reads --quick, --threads N, --repeats N (> 0), --out FILE, --data DIR, -h/--help and the
// bench's own options. Returns 0 to go on, -1 after --help, or 1 after a usage error.
inline int parseOptions(int argc, char** argv, const char* program, const char* help, CommonOptions& options,
                        std::initializer_list<BenchOption> extra = {}) {
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        const bool hasValue = k + 1 < argc;
        const auto own = std::find_if(extra.begin(), extra.end(), [&](const BenchOption& o) { return arg == o.name; });
        if (arg == "-h" || arg == "--help") {
            std::fputs(help, stdout);
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
        } else if (own != extra.end() && own->flag) {
            *own->flag = true;
        } else if (own != extra.end() && own->value && hasValue) {
            *own->value = argv[++k];
        } else {
            std::fprintf(stderr, "%s: error: bad or incomplete option '%s'\n%s", program, arg.c_str(), help);
            return 1;
        }
    }
    if (options.repeats == 0) options.repeats = options.quick ? 1 : 3;
    return 0;
}

inline constexpr int kPacket = 4;  // 4×4 pixels = 16 rays
inline constexpr int kTile = 16;   // 16×16 pixels = 256 rays

// Primary rays of `camera`, ordered tile by tile (row-major tiles), packet by packet inside a
// tile, pixel by pixel (row-major) inside a packet. Width and height must be multiples of kTile.
inline std::vector<Ray> tiledPrimaryRays(const Camera& camera) {
    const int w = camera.width(), h = camera.height();
    RELIEF_CHECK(w % kTile == 0 && h % kTile == 0);
    std::vector<Ray> rays;
    rays.reserve(size_t(w) * size_t(h));
    for (int ty = 0; ty < h; ty += kTile)
        for (int tx = 0; tx < w; tx += kTile)
            for (int py = ty; py < ty + kTile; py += kPacket)
                for (int px = tx; px < tx + kTile; px += kPacket)
                    for (int y = py; y < py + kPacket; ++y)
                        for (int x = px; x < px + kPacket; ++x)
                            rays.push_back(camera.primaryRay(float(x) + 0.5f, float(y) + 0.5f));
    return rays;
}

// Runs trace(first, count) over all tiles of `rays` in parallel (relief's parallelRanges).
template <class TraceRange>
void forEachTile(size_t rayCount, TraceRange&& trace) {
    const int64_t tiles = int64_t(rayCount / (kTile * kTile));
    parallelRanges(tiles, 1, [&](int64_t begin, int64_t end) {
        for (int64_t t = begin; t < end; ++t)
            trace(size_t(t) * kTile * kTile, size_t(kTile * kTile));
    });
}

// Best wall time of `repeats` runs of fn (the machine is shared and noisy: the best run is the
// one least disturbed).
inline double bestSeconds(int repeats, const std::function<void()>& fn) {
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        const auto start = std::chrono::steady_clock::now();
        fn();
        const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
        best = std::min(best, elapsed.count());
    }
    return best;
}

// "model name" from /proc/cpuinfo and the number of hardware threads.
inline std::string machineDescription() {
    std::ifstream in("/proc/cpuinfo");
    std::string line, model = "unknown CPU";
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0) {
            model = line.substr(line.find(':') + 2);
            break;
        }
    }
    return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}

inline std::string todayUtc() {
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    return text;
}

// 1-minute load average, to say in the report how busy the machine was.
inline std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string one;
    in >> one;
    return one.empty() ? "unknown" : one;
}

}  // namespace relief::bench
