#pragma once
// Test support shared by the quadtree, maxmip and quadtree-oriented tests: adversarial ray
// families and the comparison with the reference `exact` (DESIGN §3, contract "exact").
#include <support/reference_tracer.h>

#include <relief/surface/texel_boxes.h>

#include <gtest/gtest.h>
#include <relief/core/generators.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace relief::walk_test {

struct MapSpec {
    const char* generator;
    int width, height;
    EdgeMode edge;
    float depthRatio;  // D = ratio · max(W, H)
};

inline std::shared_ptr<const Surface> makeSurface(const MapSpec& m, uint64_t seed = 1) {
    auto hf = generateHeightfield(m.generator, m.width, m.height, seed);
    RELIEF_CHECK(hf.ok());
    const float depth = m.depthRatio * float(std::max(m.width, m.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(*hf)),
                                           depth, m.edge);
}

inline std::string describe(const MapSpec& m) {
    return std::string(m.generator) + " " + std::to_string(m.width) + "x" +
           std::to_string(m.height) + " " + std::string(toString(m.edge)) + " D/size " +
           std::to_string(m.depthRatio);
}

inline std::string describe(const Ray& r) {
    char text[200];
    std::snprintf(text, sizeof text, "o=(%a, %a, %a) d=(%a, %a, %a)", r.origin.x, r.origin.y,
                  r.origin.z, r.direction.x, r.direction.y, r.direction.z);
    return text;
}

// Every generator, both edge modes, odd and tiny sizes, shallow to steep reliefs.
inline std::vector<MapSpec> contractMaps() {
    std::vector<MapSpec> maps;
    const char* generators[] = {"sine",   "peaks6",   "fbm",  "walls",
                                "spikes", "terraces", "ramp", "flat"};
    const int sizes[][2] = {{33, 17}, {61, 64}, {5, 7}};
    const float ratios[] = {0.1f, 0.3f, 1.0f};
    const int kTinySizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 3}};
    int k = 0;
    for (const char* g : generators)
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (const auto& size : sizes) {
                maps.push_back({g, size[0], size[1], edge, ratios[k % 3]});
                ++k;
            }
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
        for (const auto& size : kTinySizes) maps.push_back({"fbm", size[0], size[1], edge, 2.0f});
    return maps;
}

class RayMaker {
public:
    RayMaker(const Surface& s, uint32_t seed)
        : m_s(s),
          m_rng(seed),
          m_w(float(s.width())),
          m_h(float(s.height())),
          m_d(std::max(s.depth(), 1e-3f)),
          m_size(std::max(m_w, m_h)) {}

    // `perFamily` rays of each family, shuffled together.
    std::vector<Ray> all(int perFamily) {
        std::vector<Ray> rays;
        for (int k = 0; k < perFamily; ++k) {
            rays.push_back(fromAbove());
            rays.push_back(fromSide());
            rays.push_back(grazing());
            rays.push_back(axisParallel());
            rays.push_back(onCellEdges());
            rays.push_back(shadow());
            rays.push_back(farAway());
            rays.push_back(longTravel());
            rays.push_back(alongAnEdgeFarAway());
        }
        return rays;
    }

    Ray fromAbove() {
        const vec3 o(u(-0.2f, 1.2f) * m_w, u(-0.2f, 1.2f) * m_h, m_d * u(1.001f, 3.0f));
        return through(o, target());
    }
    // Clamp: from beside the box, below S too (the wall is hit). Repeat: from inside the slab.
    Ray fromSide() {
        if (m_s.edge() == EdgeMode::Repeat) return through(aboveS(u(0.0f, 1.0f) * m_d), target());
        const float a = u(0.0f, 2.0f * std::numbers::pi_v<float>);
        const vec3 c(0.5f * m_w, 0.5f * m_h, 0.0f);
        const vec3 o = c + vec3(std::cos(a), std::sin(a), 0.0f) * (0.8f * m_size + 2.0f) +
                       vec3(0.0f, 0.0f, u(-0.3f, 1.3f) * m_d);
        return through(o, target());
    }
    Ray grazing() {
        const float elevation = u(0.02f, 4.0f) * std::numbers::pi_v<float> / 180.0f;
        const vec3 d = direction(u(0.0f, 2.0f * std::numbers::pi_v<float>), -elevation);
        const vec3 p = aboveS(u(0.0f, 0.2f) * m_d);
        return make(p - d * (2.0f * m_size + 4.0f), d);
    }
    Ray axisParallel() {
        const vec3 p = aboveS(u(0.0f, 0.5f) * m_d);
        const float s = m_rng() % 2 ? 1.0f : -1.0f;
        const float slope = u(0.01f, 3.0f);
        switch (m_rng() % 6) {
            case 0:
                return make(p - 3.0f * m_size * vec3(s, 0, -slope), vec3(s, 0, -slope));
            case 1:
                return make(p - 3.0f * m_size * vec3(0, s, -slope), vec3(0, s, -slope));
            case 2:
                return make(vec3(p.x, p.y, m_d * 2.0f), vec3(0, 0, -1));
            case 3:
                return make(p - 3.0f * m_size * vec3(s, 0, 0), vec3(s, 0, 0));
            case 4:
                return make(p - 3.0f * m_size * vec3(0, s, 0), vec3(0, s, 0));
            default:
                return make(p - 3.0f * m_size * vec3(s, s, -slope), vec3(s, s, -slope));
        }
    }
    // Origins exactly on cell edges and sample positions; along edges, diagonals, vertical.
    Ray onCellEdges() {
        const float x = float(int(u(0.0f, m_w))) + 0.5f, y = float(int(u(0.0f, m_h))) + 0.5f;
        const vec3 o(x, m_rng() % 2 ? y : u(0.0f, m_h), m_d * u(1.0f, 2.0f));
        const float s = m_rng() % 2 ? 1.0f : -1.0f, t = m_rng() % 2 ? 1.0f : -1.0f;
        const float slope = u(0.05f, 2.0f);
        switch (m_rng() % 4) {
            case 0:
                return make(o, vec3(0, 0, -1));
            case 1:
                return make(o, vec3(0, s, -slope));
            case 2:
                return make(o, vec3(s, t, -slope));
            default:
                return make(vec3(x, y, m_s.heightAt(x, y) + 0.25f), vec3(s, 0, -slope));
        }
    }
    // Shadow rays: just above S, going up at any elevation.
    Ray shadow() {
        const vec3 p = aboveS(std::pow(10.0f, u(-4.0f, -1.0f)) * std::max(1.0f, m_d));
        const float elevation = u(0.2f, 89.0f) * std::numbers::pi_v<float> / 180.0f;
        return make(p, direction(u(0.0f, 2.0f * std::numbers::pi_v<float>), elevation));
    }
    Ray farAway() {
        const float a = u(0.0f, 2.0f * std::numbers::pi_v<float>);
        const vec3 o(0.5f * m_w + 10.0f * m_size * std::cos(a),
                     0.5f * m_h + 10.0f * m_size * std::sin(a), m_d * u(0.5f, 20.0f));
        return through(o, target());
    }
    // Low rays crossing many cells (and many tiles in repeat mode).
    Ray longTravel() {
        const float elevation = u(0.0f, 1.0f) * std::numbers::pi_v<float> / 180.0f;
        const vec3 d = direction(u(0.0f, 2.0f * std::numbers::pi_v<float>), -elevation);
        return make(aboveS(u(0.5f, 1.0f) * m_d), d);
    }

      // Nearly parallel to a cell edge and one ulp beside it, where coordinates are large (repeat:
    // thousands of texels from the origin): float positions round onto the edge while the ray
    // stays on its side for hundreds of texels. The origin lies inside the box (below its top):
    // an entry point computed on the box would itself round onto the edge, and `exact` would
    // start in the cell beyond it (a reference artifact, not a contract matter).
    Ray alongAnEdgeFarAway() {
        const bool repeat = m_s.edge() == EdgeMode::Repeat;
        const float far = repeat ? 4096.0f : 0.0f;
        const float edge = far + std::floor(u(0.0f, m_h - 1.0f)) + 0.5f;
        const float side = m_rng() % 2 ? 1.0f : -1.0f;
        const float y = std::nextafter(edge, edge - side);  // one ulp off the edge
        const float x = far + u(0.0f, m_w);
        const float s = m_s.heightAt(x, y);
        const float z = s + u(0.0f, 1.0f) * (m_s.depth() - s);
        const float dx = m_rng() % 2 ? 1.0f : -1.0f, dy = side * u(1e-9f, 1e-6f);
        Ray r = make(vec3(x, y, z), vec3(dx, dy, -u(0.0f, 0.05f)));
        if (m_rng() % 2) r = make(vec3(y, x, z), vec3(dy, dx, r.direction.z));  // along y
        return r;
    }

private:
    float u(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(m_rng); }
    vec3 xy() {
        if (m_s.edge() == EdgeMode::Repeat)
            return vec3(u(-1.5f, 2.5f) * m_w, u(-1.5f, 2.5f) * m_h, 0);
        return vec3(u(0.0f, m_w), u(0.0f, m_h), 0.0f);
    }
    vec3 aboveS(float clearance) {
        vec3 p = xy();
        p.z = m_s.heightAt(p.x, p.y) + clearance;
        return p;
    }
    vec3 target() {
        vec3 p = xy();
        p.z = u(0.0f, 1.0f) * m_s.depth();
        return p;
    }
    static vec3 direction(float azimuth, float elevation) {
        return vec3(std::cos(azimuth) * std::cos(elevation),
                    std::sin(azimuth) * std::cos(elevation), std::sin(elevation));
    }
    static Ray make(const vec3& o, const vec3& d) {
        Ray r;
        r.origin = o;
        r.direction = glm::normalize(d);
        return r;
    }
    static Ray through(const vec3& o, const vec3& to) { return make(o, to - o); }

    const Surface& m_s;
    std::mt19937 m_rng;
    float m_w, m_h, m_d, m_size;
};

struct Tally {
    size_t rays = 0, hits = 0, wrong = 0;
    double maxError = 0.0;
    int64_t steps = 0;
};

// The texel-box reference (surface/texel_boxes.h), for the box-surface = 2 walks.
struct TexelBoxReference {
    std::shared_ptr<const Surface> surface;
    Hit trace(const Ray& ray) const { return firstTexelBoxHit(*surface, ray); }
};

// Traces `rays` with `tracer` and `reference`; counts wrong hits (hit/miss differs, or
// |Δt| > 1e-3) and reports the first few.
template <class Impl, class Reference>
void compareWith(const Impl& tracer, const Reference& reference, const std::vector<Ray>& rays,
                 const std::string& what, Tally& tally) {
    for (const Ray& ray : rays) {
        const Hit ref = reference.trace(ray);
        const Hit got = tracer.trace(ray);
        ++tally.rays;
        tally.steps += got.steps;
        tally.hits += ref.hit;
        const double error = ref.hit && got.hit ? std::abs(double(got.t) - double(ref.t)) : 0.0;
        tally.maxError = std::max(tally.maxError, error);
        if (ref.hit == got.hit && error <= 1e-3) continue;
        if (++tally.wrong <= 5)
            ADD_FAILURE() << what << ": " << describe(ray) << " reference " << ref.hit
                          << " t=" << ref.t << ", got " << got.hit << " t=" << got.t;
    }
}

// compareWith the reference `exact` (S).
template <class Impl>
void compareWithExact(const Impl& tracer, const std::shared_ptr<const Surface>& surface,
                      const std::vector<Ray>& rays, const std::string& what, Tally& tally) {
    compareWith(tracer, testing::ReferenceTracer(surface), rays, what, tally);
}

}  // namespace relief::walk_test

namespace relief::walk_test {

// Traces `perFamily` rays of every family on every contract map with the tracer made by
// `make(surface)`, against `makeReference(surface)`. Returns the totals (wrong hits are test
// failures).
template <class Make, class MakeReference>
Tally contractOnAllMapsWith(Make make, MakeReference makeReference, int perFamily,
                            const std::string& what) {
    Tally tally;
    uint32_t seed = 11;
    for (const MapSpec& m : contractMaps()) {
        const auto surface = makeSurface(m, seed);
        const auto tracer = make(surface);
        RayMaker maker(*surface, seed++);
        compareWith(tracer, makeReference(surface), maker.all(perFamily),
                    what + " on " + describe(m), tally);
    }
    std::printf("[ %s ] %zu rays (%zu reference hits), %zu wrong, max |dt| %.2g, %.1f steps/ray\n",
                what.c_str(), tally.rays, tally.hits, tally.wrong, tally.maxError,
                double(tally.steps) / double(std::max<size_t>(tally.rays, 1)));
    return tally;
}

// contractOnAllMapsWith the reference `exact` (S).
template <class Make>
Tally contractOnAllMaps(Make make, int perFamily, const std::string& what) {
    return contractOnAllMapsWith(
        make, [](const std::shared_ptr<const Surface>& s) { return testing::ReferenceTracer(s); },
        perFamily, what);
}

// A capped walk stops at a cursor that never passed the first hit (the walk is conservative).
template <class Make>
void cursorNeverPassesFirstHit(Make make, const std::string& what) {
    size_t checked = 0;
    for (const MapSpec& m : {MapSpec{"fbm", 61, 64, EdgeMode::Clamp, 0.3f},
                             MapSpec{"walls", 33, 17, EdgeMode::Repeat, 0.3f},
                             MapSpec{"spikes", 64, 64, EdgeMode::Clamp, 1.0f}}) {
        const auto surface = makeSurface(m, 3);
        const testing::ReferenceTracer exact(surface);
        RayMaker maker(*surface, 5);
        for (int cap : {1, 3, 8, 20}) {
            const auto tracer = make(surface, cap);
            for (const Ray& ray : maker.all(40)) {
                const Hit ref = exact.trace(ray), got = tracer.trace(ray);
                EXPECT_LE(got.steps, cap);
                if (!ref.hit || !got.hit) {
                    EXPECT_FALSE(ref.hit && !got.hit) << what << " cap " << cap << describe(ray);
                    continue;
                }
                ++checked;
                EXPECT_LE(got.t, ref.t + 1e-4f) << what << " cap " << cap << " " << describe(ray);
            }
        }
    }
    EXPECT_GT(checked, 1000u);
}

}  // namespace relief::walk_test
