#pragma once
// Test helpers shared by safety_sd_test.cpp, safety_cc_test.cpp and safety_common_test.cpp:
// surfaces (standard generators and the paper's Fig. 11 kind of relief), an exact count of how
// often a ray passes between above and below S, and a tally against the exact reference.
#include <support/ray_sets.h>
#include <support/reference_tracer.h>

#include <relief/core/generators.h>
#include <relief/techniques/safety_common/safety_march.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace relief::safety::testing {

// Fig. 11 of the paper: one-texel-wide walls, pits and pillars on a flat floor (plus a ramp so
// that planes are not all horizontal).
inline std::shared_ptr<const Heightfield> thinFeatures(int w, int h) {
    auto hf = std::make_shared<Heightfield>();
    hf->width = w, hf->height = h;
    hf->samples.assign(size_t(w) * size_t(h), 0.3f);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            float& z = hf->at(i, j);
            if (i == w / 3 && j > 1 && j < h - 2) z = 1.0f;               // wall along y
            if (j == h / 2 && i > w / 2 && i < w - 1) z = 0.9f;           // wall along x
            if ((i * 7 + j * 3) % 11 == 0) z = 0.0f;                      // one-texel pits
            if ((i + 2 * j) % 13 == 5) z = 0.8f;                          // one-texel pillars
            if (i >= w - 3) z = 0.3f + 0.2f * float(j) / float(h);        // a ramp strip
        }
    return hf;
}

inline std::shared_ptr<const Surface> makeSurface(const std::string& gen, int w, int h,
                                                  EdgeMode edge, float depthRatio,
                                                  uint64_t seed = 1) {
    std::shared_ptr<const Heightfield> hf =
        gen == "fig11" ? thinFeatures(w, h)
                       : std::make_shared<const Heightfield>(*generateHeightfield(gen, w, h, seed));
    return std::make_shared<const Surface>(hf, depthRatio * float(w), edge);
}

// How many times the ray o + t·d (t ∈ [0, t1]) passes between above and below S, with a
// hysteresis of eps (touching S is not a crossing). Exact: between cell boundaries and each
// cell's diagonal kink the ray's height above S is linear. In clamp mode the count stops where
// the ray leaves the box.
inline int transitions(const Surface& s, const dvec3& o, const dvec3& d, double t1, double eps) {
    std::vector<double> ts = {0.0, t1};
    for (int axis = 0; axis < 2; ++axis) {
        if (d[axis] == 0.0) continue;
        const double a0 = o[axis], a1 = o[axis] + t1 * d[axis];
        for (double c = std::ceil(std::min(a0, a1) - 0.5) + 0.5; c <= std::max(a0, a1); c += 1.0)
            ts.push_back((c - o[axis]) / d[axis]);
    }
    std::sort(ts.begin(), ts.end());
    int state = 1, count = 0;  // starts above
    auto visit = [&](double f) {
        if (f > eps && state < 0) state = 1, ++count;
        if (f < -eps && state > 0) state = -1, ++count;
    };
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
        const double ta = std::max(0.0, ts[k]), tb = std::min(t1, ts[k + 1]);
        if (!(tb > ta)) continue;
        const dvec3 mid = o + 0.5 * (ta + tb) * d;
        if (s.edge() == EdgeMode::Clamp &&
            (mid.x < 0 || mid.y < 0 || mid.x > s.width() || mid.y > s.height()))
            break;
        const int ci = int(std::floor(mid.x - 0.5)), cj = int(std::floor(mid.y - 0.5));
        const CellPlanes planes = s.cellPlanes(ci, cj);
        auto f = [&](double t) {
            const dvec3 p = o + t * d;
            const double u = p.x - (ci + 0.5), v = p.y - (cj + 0.5);
            const double p1 = planes.first.z0 + planes.first.sx * u + planes.first.sy * v;
            const double p2 = planes.second.z0 + planes.second.sx * u + planes.second.sy * v;
            return p.z - std::max(p1, p2);
        };
        auto diff = [&](double t) {
            const dvec3 p = o + t * d;
            const double u = p.x - (ci + 0.5), v = p.y - (cj + 0.5);
            return (planes.first.z0 + planes.first.sx * u + planes.first.sy * v) -
                   (planes.second.z0 + planes.second.sx * u + planes.second.sy * v);
        };
        visit(f(ta));
        const double da = diff(ta), db = diff(tb);
        if ((da < 0) != (db < 0) && da != db) visit(f(ta + (tb - ta) * da / (da - db)));
        visit(f(tb));
    }
    return count;
}

struct Tally {
    size_t rays = 0, wrong = 0, beyond = 0, both = 0, far = 0;  // far: |dt| > 0.5 (DESIGN §8)
    double maxError = 0.0, sumError = 0.0;
    void add(const Hit& h, const Hit& ref) {
        ++rays;
        if (h.hit != ref.hit) {
            ++wrong;
            return;
        }
        if (!h.hit) return;
        const double e = std::abs(double(h.t) - double(ref.t));
        ++both;
        sumError += e;
        maxError = std::max(maxError, e);
        if (e > 1e-3) ++beyond;
        if (e > 0.5) ++far;
    }
    void add(const Tally& o) {
        rays += o.rays, wrong += o.wrong, beyond += o.beyond, both += o.both, far += o.far;
        sumError += o.sumError, maxError = std::max(maxError, o.maxError);
    }
    double meanError() const { return both ? sumError / double(both) : 0.0; }
};

template <class T>
Tally tally(const T& tracer, const Surface& s, const std::vector<Ray>& rays) {
    const relief::testing::ReferenceTracer exact(std::make_shared<const Surface>(s));
    Tally t;
    for (const Ray& r : rays) t.add(tracer.trace(r), exact.trace(r));
    return t;
}

struct MapCase {
    const char* generator;
    int width, height;
    EdgeMode edge;
    float depthRatio;
};

// The harness's generators and both edge modes, at two sizes, plus the thin-feature relief.
inline std::vector<MapCase> standardCases() {
    std::vector<MapCase> cases;
    for (const char* g : {"sine", "peaks6", "fbm", "walls", "spikes", "terraces", "ramp", "flat",
                          "fig11"})
        for (EdgeMode e : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            cases.push_back({g, 37, 23, e, 0.25f});
            cases.push_back({g, 48, 48, e, 0.25f});
        }
    return cases;
}

inline TechniqueInput inputFor(std::shared_ptr<const Surface> s,
                               std::vector<std::pair<std::string, double>> params,
                               std::span<const ParamSpec> specs) {
    ParamValues values;
    for (const ParamSpec& p : specs) values.set(std::string(p.name), p.defaultValue);
    for (auto& [k, v] : params) values.set(k, v);
    return TechniqueInput{std::move(s), std::move(values), nullptr};
}

// Traces all standard cases' random and adversarial rays (≥ 1e5 in all) and tallies them;
// exact: fail on any difference beyond the contract.
template <class Make>
Tally contractOnAllMaps(Make make, int perKind, const char* label, bool exact = true) {
    Tally all;
    uint32_t seed = 7;
    for (const MapCase& c : standardCases()) {
        auto s = makeSurface(c.generator, c.width, c.height, c.edge, c.depthRatio);
        const auto tracer = make(s);
        ::relief::testing::RaySets sets(*s, seed++);
        const Tally t = tally(tracer, *s, sets.all(perKind));
        if (exact && (t.wrong || t.beyond))
            ADD_FAILURE() << label << ": " << t.wrong << " wrong hit/miss, " << t.beyond
                          << " beyond 1e-3 on " << c.generator << " " << c.width << "x"
                          << c.height << " " << toString(c.edge);
        all.add(t);
    }
    std::printf("[ safety   ] %-34s rays %zu, hit/miss differs %zu, |dt|>1e-3 %zu, |dt|>0.5 %zu, "
                "mean |dt| %.3g, max |dt| %.3g\n",
                label, all.rays, all.wrong, all.beyond, all.far, all.meanError(), all.maxError);
    return all;
}

// Rays from outside the box: far around it, and low at its sides (grazing rays through the side
// walls, the ones that see under overhanging views), aimed at random points of the box.
inline std::vector<Ray> exteriorRays(const Surface& s, int count, std::mt19937& rng) {
    auto uniform = [&](double lo, double hi) {
        return float(std::uniform_real_distribution<>(lo, hi)(rng));
    };
    const vec3 size(float(s.width()), float(s.height()), s.depth());
    std::vector<Ray> rays;
    for (int k = 0; k < count; ++k) {
        vec3 o;
        if (k % 2) {
            const float el = glm::radians(uniform(-2.0, 89.0)), az = uniform(0.0, 6.2832);
            const float radius = uniform(0.6, 3.0) * glm::length(size);
            o = 0.5f * size + radius * vec3(std::cos(el) * std::cos(az),
                                            std::cos(el) * std::sin(az), std::sin(el));
        } else {  // just outside a side face, at any height up to above the top
            const int side = k / 2 % 4;
            const float u = uniform(0, 1), z = uniform(0, 1.3 * s.maxZ() + 0.1);
            o = side == 0   ? vec3(-uniform(0.01, 3), u * size.y, z)
                : side == 1 ? vec3(size.x + uniform(0.01, 3), u * size.y, z)
                : side == 2 ? vec3(u * size.x, -uniform(0.01, 3), z)
                            : vec3(u * size.x, size.y + uniform(0.01, 3), z);
        }
        const vec3 target(uniform(0, size.x), uniform(0, size.y), uniform(0, s.maxZ() + 0.1));
        rays.push_back(Ray{o, glm::normalize(target - o), kInfinity});
    }
    return rays;
}

}  // namespace relief::safety::testing
