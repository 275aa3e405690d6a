#pragma once
// Test support for the SIMD packet paths (quadtree, maxmip, exact, cone, safety-cc) and the ISA
// dispatch: hits compared bit for bit, a check run once per Highway target this machine has, and
// the maps and coherent rays (camera, shadow) every packet test traces.
#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <relief/core/check.h>
#include <relief/core/generators.h>
#include <relief/core/math.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/camera.h>
#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/registry.h>
#include <relief/techniques/technique.h>
#include <support/walk_test_support.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace relief::packet_test {

// Every field of the hit, floats by their bits.
inline bool identical(const Hit& a, const Hit& b) {
    const auto bits = [](float v) { return std::bit_cast<uint32_t>(v); };
    return a.hit == b.hit && bits(a.t) == bits(b.t) && bits(a.position.x) == bits(b.position.x) &&
           bits(a.position.y) == bits(b.position.y) &&
           bits(a.position.z) == bits(b.position.z) && a.steps == b.steps &&
           a.fetches == b.fetches;
}

// `run` once per compiled target this machine has (AVX-512, AVX2, SSE4, the fallback), with the
// dispatch forced to it.
template <class Run>
void forEachTarget(Run run) {
    const int64_t supported = hwy::SupportedTargets();
    for (const int64_t target :
         {int64_t(HWY_AVX3), int64_t(HWY_AVX2), int64_t(HWY_SSE4), int64_t(HWY_EMU128)}) {
        if ((supported & target) == 0) continue;
        hwy::SetSupportedTargetsForTest(target);
        SCOPED_TRACE(packetWalkTarget());
        run();
    }
    hwy::SetSupportedTargetsForTest(0);
}

struct Counts {
    size_t rays = 0, hits = 0, differences = 0;
};

using TraceSpan = std::function<void(std::span<const Ray>, std::span<Hit>)>;
using TraceOne = std::function<Hit(const Ray&)>;

// `packets` over the rays in 256-ray batches and odd-sized spans (a partly filled packet) against
// `scalar` ray by ray: every difference counted, the first five reported.
inline void compareBatches(const TraceSpan& packets, const TraceOne& scalar,
                           const std::vector<Ray>& rays, const std::string& what, Counts& counts) {
    std::vector<Hit> hits(rays.size());
    const std::span<const Ray> all(rays);
    for (size_t begin = 0, k = 0; begin < rays.size(); ++k) {
        const size_t size = std::min(rays.size() - begin, k % 3 == 2 ? size_t(37) : size_t(256));
        packets(all.subspan(begin, size), std::span<Hit>(hits).subspan(begin, size));
        begin += size;
    }
    size_t reported = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        const Hit want = scalar(rays[k]);
        ++counts.rays;
        counts.hits += want.hit;
        if (identical(want, hits[k])) continue;
        ++counts.differences;
        if (reported++ < 5)
            ADD_FAILURE() << what << " " << walk_test::describe(rays[k]) << ": scalar hit "
                          << want.hit << " t " << want.t << " steps " << want.steps
                          << ", packet hit " << hits[k].hit << " t " << hits[k].t << " steps "
                          << hits[k].steps;
    }
}

using Overrides = std::vector<std::pair<std::string, double>>;

// The registry's row `name` over the surface, with these parameters.
inline std::unique_ptr<Tracer> rowTracer(const std::string& name,
                                         const std::shared_ptr<const Surface>& surface,
                                         const Overrides& overrides) {
    auto tracer = createTracer(name, surface, overrides);
    RELIEF_CHECK(tracer.ok());
    return std::move(*tracer);
}

// "defaults", or the first parameter as NAME=V.
inline std::string describe(const Overrides& overrides) {
    return overrides.empty() ? "defaults"
                             : overrides[0].first + "=" + std::to_string(int(overrides[0].second));
}

// A registry row's packet path against its scalar path (PacketTracer::scalarPath, ray by ray).
inline void compareRowPaths(const Tracer& tracer, const std::vector<Ray>& rays,
                            const std::string& what, Counts& counts) {
    const auto* packets = dynamic_cast<const PacketTracer*>(&tracer);
    ASSERT_NE(packets, nullptr) << what;
    compareBatches(
        [&](std::span<const Ray> batch, std::span<Hit> hits) { packets->traceBatch(batch, hits); },
        [&](const Ray& ray) {
            Hit hit;
            packets->scalarPath().traceBatch({&ray, 1}, {&hit, 1});
            return hit;
        },
        rays, what, counts);
}

inline std::shared_ptr<const Surface> surfaceOf(Heightfield hf, float depthRatio, EdgeMode edge) {
    const float depth = depthRatio * float(std::max(hf.width, hf.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(hf)),
                                           depth, edge);
}

using NamedSurfaces = std::vector<std::pair<std::string, std::shared_ptr<const Surface>>>;

// The maps the packet tests trace coherent rays over: fbm, terraces, walls and a real DEM.
inline NamedSurfaces coherentRayMaps(EdgeMode edge) {
    NamedSurfaces maps;
    const auto add = [&](const std::string& name, Result<Heightfield> hf, float depthRatio) {
        RELIEF_CHECK(hf.ok());
        maps.emplace_back(name, surfaceOf(std::move(*hf), depthRatio, edge));
    };
    add("fbm 257x200", generateHeightfield("fbm", 257, 200, 3), 0.1f);
    add("terraces 128", generateHeightfield("terraces", 128, 128, 5), 0.3f);
    add("walls 96x80", generateHeightfield("walls", 96, 80, 5), 0.2f);
    add("colorado 400",
        loadHeightfield(std::string(RELIEF_SOURCE_DIR) + "/data/colorado-elevation-400.png"), 0.1f);
    return maps;
}

// The primary rays of a 96x80 orbit view at `elevation` (azimuth 30°).
inline std::vector<Ray> cameraRays(const Surface& surface, float elevation) {
    OrbitView view;
    view.elevationDeg = elevation;
    view.azimuthDeg = 30.0f;
    return primaryRays(Camera(view, surface, 96, 80));
}

// Shadow rays from the hits `exact` gives the rays toward a light at 30° (as the cpu-peers bench
// makes them: from just above the hit).
inline std::vector<Ray> shadowRays(const std::vector<Ray>& primary, const TraceOne& exact) {
    const float light = 30.0f * std::numbers::pi_v<float> / 180.0f;
    const vec3 toLight(std::cos(light) * 0.8f, std::cos(light) * 0.6f, std::sin(light));
    std::vector<Ray> shadow;
    for (const Ray& ray : primary) {
        const Hit hit = exact(ray);
        if (hit.hit) shadow.push_back(Ray{hit.position + vec3(0.0f, 0.0f, 1e-3f), toLight});
    }
    return shadow;
}

// Over one of coherentRayMaps: the camera rays at 15.3°, 40.2° and 65.1°, the shadow rays from
// their `exact` hits, and 300 rays of each random family (walk_test::RayMaker).
inline std::vector<Ray> viewAndRandomRays(const Surface& surface, const TraceOne& exact) {
    std::vector<Ray> rays;
    for (float elevation : {15.3f, 40.2f, 65.1f}) {
        const std::vector<Ray> primary = cameraRays(surface, elevation);
        const std::vector<Ray> shadow = shadowRays(primary, exact);
        rays.insert(rays.end(), primary.begin(), primary.end());
        rays.insert(rays.end(), shadow.begin(), shadow.end());
    }
    walk_test::RayMaker maker(surface, 77);
    const std::vector<Ray> random = maker.all(300);
    rays.insert(rays.end(), random.begin(), random.end());
    return rays;
}

}  // namespace relief::packet_test
