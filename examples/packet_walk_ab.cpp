// The rows' packet paths (quadtree, maxmip, exact, cone, safety-cc: PacketTracer) against their
// scalar paths, side by side in one process on the same primary rays
// (docs/benchmarks-packets.md): per row, map and elevation, the two traced in turn (A B A B ...),
// each pass through traceAll (256-ray batches in parallel), the ratio taken pair by pair, and
// every hit compared bit for bit.
//
//   relief_packet_ab [--threads N] [--reps R] [--size WxH] [--edge clamp|repeat]
//                    [--isa avx3|avx2|sse4] [--rows quadtree,maxmip,exact,cone,safety-cc] [--tiles]
//                    SOURCE...
//   --isa: limit the packet paths' dispatch to that target (default: the best this CPU has)
//   a row A~B: row A against row B instead of a row's packets against its scalar path (e.g.
//   quadtree:traversal=1~quadtree); differences then count hit, t or position only
//   --tiles: the rays in the Embree packets' order (4×4 pixel tiles, bench::packetOrder)
//   --elevations: the views' camera elevations in degrees, comma-separated (default
//   15.3,40.2,65.1)
//   --shadows: the view's shadow rays instead (as the bench's: from a light at 30° elevation
//   toward the primary hits that face it, in that order)
//   SOURCE: gen:NAME:WxH[:seed] or FILE[@crop=X,Y,W,H] (as `relief render --heightfield`)
#include <relief/bench/presets.h>
#include <relief/bench/timing.h>
#include <relief/core/parallel.h>
#include <relief/render/camera.h>
#include <relief/render/renderer.h>
#include <relief/render/surface_source.h>
#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/registry.h>

#include <hwy/targets.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

using namespace relief;

double seconds(const Tracer& tracer, const std::vector<Ray>& rays, std::vector<Hit>& hits) {
    const auto start = std::chrono::steady_clock::now();
    traceAll(tracer, rays, hits);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool same(const Hit& a, const Hit& b, bool counts) {
    const auto bits = [](float v) { return std::bit_cast<uint32_t>(v); };
    return a.hit == b.hit && bits(a.t) == bits(b.t) && bits(a.position.x) == bits(b.position.x) &&
           bits(a.position.y) == bits(b.position.y) &&
           bits(a.position.z) == bits(b.position.z) &&
           (!counts || (a.steps == b.steps && a.fetches == b.fetches));
}

}  // namespace

int main(int argc, char** argv) {
    int threads = 2, reps = 7, width = 640, height = 512;
    std::string edge = "clamp";
    bool tiles = false;  // rays in the Embree packets' order (bench::packetOrder), not by rows
    bool shadows = false;  // the views' shadow rays, not their primary rays
    std::vector<std::string> sources, rows = {"quadtree", "maxmip", "exact"};
    std::vector<float> elevations = {15.3f, 40.2f, 65.1f};
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a == "--threads" && k + 1 < argc) threads = std::atoi(argv[++k]);
        else if (a == "--reps" && k + 1 < argc) reps = std::max(1, std::atoi(argv[++k]));
        else if (a == "--size" && k + 1 < argc) std::sscanf(argv[++k], "%dx%d", &width, &height);
        else if (a == "--edge" && k + 1 < argc) edge = argv[++k];
        else if (a == "--tiles") tiles = true;
        else if (a == "--shadows") shadows = true;
        else if (a == "--rows" && k + 1 < argc) {
            rows.clear();
            for (std::string list = argv[++k]; !list.empty();) {
                const size_t comma = list.find(',');
                rows.push_back(list.substr(0, comma));
                list = comma == std::string::npos ? "" : list.substr(comma + 1);
            }
        }
        else if (a == "--elevations" && k + 1 < argc) {
            elevations.clear();
            const char* list = argv[++k];
            for (const char* c = list;;) {
                char* end = nullptr;
                const float elevation = std::strtof(c, &end);
                if (end == c || (*end != ',' && *end != '\0')) {
                    std::fprintf(stderr, "--elevations: degrees, comma-separated (got \"%s\")\n",
                                 list);
                    return 2;
                }
                elevations.push_back(elevation);
                if (*end == '\0') break;
                c = end + 1;
            }
        }
        else if (a == "--isa" && k + 1 < argc) {
            const std::string isa = argv[++k];
            hwy::SetSupportedTargetsForTest(isa == "avx3"   ? HWY_AVX3
                                            : isa == "avx2" ? HWY_AVX2
                                            : isa == "sse4" ? HWY_SSE4
                                                            : HWY_EMU128);
        }
        else sources.push_back(a);
    }
    if (sources.empty()) {
        std::fprintf(stderr, "usage: %s [--threads N] [--reps R] [--size WxH] "
                             "[--edge clamp|repeat] [--isa avx3|avx2|sse4] "
                             "[--rows quadtree,maxmip,exact,cone,safety-cc] [--tiles] [--shadows] "
                             "[--elevations E,...] SOURCE...\n", argv[0]);
        return 2;
    }
    if ((tiles || shadows) && (width % 16 != 0 || height % 16 != 0)) {
        std::fprintf(stderr, "--tiles, --shadows: the packets' order covers sizes in multiples of 16 (got %dx%d)\n",
                     width, height);
        return 2;
    }
    const ThreadLimit limit(threads);
    std::printf("packet target %s, %d threads, %dx%d %s, %d pairs, edge %s\n\n",
                packetWalkTarget(), threads, width, height,
                shadows ? "views' shadow rays" : "primary rays", reps, edge.c_str());
    std::printf("| row | map | elevation | scalar Mrays/s | packets Mrays/s | speed-up (median, min–max of "
                "pairs) | hits | differences | steps/ray | fetches/ray |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& source : sources) {
        SurfaceOptions options;
        options.source = source;
        options.edge = edge;
        auto hf = loadHeightfield(options);
        if (!hf) {
            std::fprintf(stderr, "%s\n", hf.error().message.c_str());
            return 1;
        }
        auto surface = makeSurface(options, *hf);
        if (!surface) {
            std::fprintf(stderr, "%s\n", surface.error().message.c_str());
            return 1;
        }
        for (const std::string& row : rows) {
        const size_t tilde = row.find('~');
        const bool pair = tilde != std::string::npos;
        // NAME[:PARAM=VALUE...], as the bench's rows
        const auto create = [&](const std::string& spec) -> Result<std::unique_ptr<Tracer>> {
            auto parsed = bench::parseRowSpec(spec);
            if (!parsed) return parsed.error();
            return createTracer(parsed->info->name, *surface, parsed->params);
        };
        auto tracer = create(row.substr(0, tilde));
        if (!tracer) {
            std::fprintf(stderr, "%s\n", tracer.error().message.c_str());
            return 1;
        }
        std::unique_ptr<Tracer> peer;  // row B of a pair
        if (pair) {
            auto made = create(row.substr(tilde + 1));
            if (!made) {
                std::fprintf(stderr, "%s\n", made.error().message.c_str());
                return 1;
            }
            peer = std::move(*made);
        }
        const auto* packetRow = dynamic_cast<const PacketTracer*>(tracer->get());
        if (!packetRow && !pair) {
            std::fprintf(stderr,
                         "%s: no packet path here (RELIEF_PACKETS=0, or not a packet row)\n",
                         row.c_str());
            return 1;
        }
        const Tracer& packets = **tracer;
        const Tracer& scalar = pair ? *peer : packetRow->scalarPath();
        for (const float elevation : elevations) {
            OrbitView view;
            view.elevationDeg = elevation;
            view.distance = 1.0f;
            std::vector<Ray> rays = primaryRays(Camera(view, **surface, width, height));
            if (shadows) {
                std::vector<Hit> primary(rays.size());
                traceAll(scalar, rays, primary);
                const vec3 light = bench::towardsLight(30.0f);
                rays = raysFromTheLight(
                           **surface, bench::shadowPoints(**surface, primary, width, height, light),
                           light)
                           .rays;
            } else if (tiles) {
                rays = bench::inPacketOrder(rays, bench::packetOrder(width, height));
            }
            std::vector<Hit> a(rays.size()), b(rays.size());
            seconds(scalar, rays, a);  // warm-up, and the hits to compare
            seconds(packets, rays, b);
            size_t differences = 0, hits = 0;
            double steps = 0, fetches = 0;
            for (size_t k = 0; k < rays.size(); ++k) {
                differences += !same(a[k], b[k], !pair);
                hits += a[k].hit;
                steps += b[k].steps;
                fetches += b[k].fetches;
            }
            std::vector<double> ts, tp, ratios;
            for (int r = 0; r < reps; ++r) {
                ts.push_back(seconds(scalar, rays, a));
                tp.push_back(seconds(packets, rays, b));
                ratios.push_back(ts.back() / tp.back());
            }
            const double n = double(rays.size()) * 1e-6;
            std::printf(
                "| %s | %s | %.1f | %.2f | %.2f | %.2f (%.2f–%.2f) | %zu | %zu | %.1f | %.1f |\n",
                row.c_str(), source.c_str(), elevation, n / bench::median(ts), n / bench::median(tp),
                bench::median(ratios), *std::min_element(ratios.begin(), ratios.end()),
                *std::max_element(ratios.begin(), ratios.end()), hits, differences,
                steps / double(rays.size()), fetches / double(rays.size()));
            std::fflush(stdout);
        }
        }
    }
    return 0;
}
