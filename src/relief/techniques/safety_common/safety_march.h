#pragma once
// The marching of §5.2.2 shared by `safety-sd` and `safety-cc`, templated on the shape (no
// virtual call per ray): positions only on the class's centerlines, a jump of i centerlines per
// map fetch, i = 0 as one naive step (the cells up to the next centerline), bisection on integer
// centerlines once a position is below S, and the exact two-triangle test of the reference on
// the (at most two) cells between the last two centerlines.
//
// Exactness argument: a position classified "above" is above S by more than a margin that
// covers float error, so it is truly above; inside a safety shape a ray from a point above S
// crosses S at most once, so above → above means no crossing and above → below means exactly
// one, which the bisection keeps in its interval. A position classified "below" only within the
// margin may be a false alarm: the final exact test then finds nothing and the march resumes
// from there (it is above S by that same test).
#include <relief/surface/cell_walk.h>
#include <relief/techniques/safety_common/safety_maps.h>
#include <relief/techniques/technique.h>

#include <atomic>
#include <cmath>
#include <memory>

namespace relief::safety {

struct MarchOptions {
    int maxSteps = 0;               // 0 = none (exact)
    double phiMaxDeg = 90.0;        // the maps' φ_max; rays outside it take the exact walk
    bool exterior = false;          // maps for exterior rays: interior origins take the exact walk
    bool viewDependent = false;     // §7: linear along the ray between test positions
    bool positiveDistance = false;  // §7: safety distances clamped to ≥ 1
    bool phiOutside = false;        // rays outside φ_max march on the maps too (the paper's way)
};

// Fewer centerlines than this inside the box (near-vertical rays): the exact walk is cheaper.
inline constexpr int kMinCenterlines = 3;
inline constexpr int kFarStep = 1 << 20;
// What safety_common/safety_march.glsl and safety_cc/safety_cc.glsl read (glslConstants).
inline constexpr GlslConstant kSafetyMarchGlslConstants[] = {
    {"kMinCenterlines", double(kMinCenterlines), true},
    {"kFarStep", double(kFarStep), true},
};

// Does a ray with this direction satisfy the viewing-angle restriction the maps were built for
// (§6.2.5: elevation angle below φ_max)? A hair stricter than the build, which includes the
// bound itself.
inline bool rayWithinPhiMax(const vec3& d, double tanPhi) {
    if (!std::isfinite(tanPhi)) return true;
    const double horizontal = std::sqrt(double(d.x) * d.x + double(d.y) * d.y);
    return double(d.z) <= (tanPhi - 1e-6) * horizontal;
}

// For the renderer's warning: true when every ray given (e.g. the primary rays, or those along
// the image border) is within φ_max, i.e. no pixel will take the slow fallback.
inline bool viewWithinPhiMax(std::span<const Ray> rays, double phiMaxDeg) {
    const double t = tanPhiMax(phiMaxDeg);
    for (const Ray& r : rays)
        if (!rayWithinPhiMax(r.direction, t)) return false;
    return true;
}

// Do exterior-ray maps (§6.2) serve a ray from this origin? Yes when the origin is outside the
// open box, or above the highest sample (nothing of S lies behind it): such a ray reaches every
// test position without having met S, which is what the exterior build assumes. Clamp mode
// only (exterior maps are not built for repeat mode).
inline bool originIsExterior(const Surface& s, const vec3& o) {
    return o.z >= s.maxZ() || o.z <= 0.0f || o.x <= 0.0f || o.y <= 0.0f ||
           o.x >= float(s.width()) || o.y >= float(s.height());
}

// The safety distance map as a shape: the stored i, whatever the ray's height.
class DistanceShape {
public:
    explicit DistanceShape(std::shared_ptr<const DistanceMap> map) : m_map(std::move(map)) {}
    int step(int cls, int i, int j, float /*z*/, float /*slope*/) const {
        return m_map->at(cls, i, j);
    }
    const DistanceMap& map() const { return *m_map; }

private:
    std::shared_ptr<const DistanceMap> m_map;
};

// The cylinder-cone: i = max(r, ⌊max(p_z − z0, 0)/(s_c − s_d)⌋) (§6.3.1, with ⌊⌋, see
// safety_cc.h), s_d = the ray's rise per centerline.
class ConeShape {
public:
    explicit ConeShape(std::shared_ptr<const CylinderConeMap> map) : m_map(std::move(map)) {}
    int step(int cls, int i, int j, float z, float slope) const {
        const ConeTexel& c = m_map->at(cls, i, j);
        const float above = z - c.z0;
        if (above <= 0.0f) return c.r;
        const float closing = c.slope - slope;
        if (closing <= 0.0f) return kFarStep;  // the ray rises at least as fast as the cone
        return std::max(c.r, int(std::min(above / closing, float(kFarStep))));
    }
    const CylinderConeMap& map() const { return *m_map; }

private:
    std::shared_ptr<const CylinderConeMap> m_map;
};

template <class Shape>
class SafetyTracer {
public:
    SafetyTracer(std::shared_ptr<const Surface> surface, Shape shape, MarchOptions options)
        : m_surface(std::move(surface)),
          m_shape(std::move(shape)),
          m_options(options),
          m_tanPhi(tanPhiMax(options.phiMaxDeg)),
          m_margin(1e-4f * (1.0f + m_surface->maxZ())),
          m_fallbacks(std::make_shared<std::atomic<uint64_t>>(0)) {}

    Hit trace(const Ray& ray) const;

    // One ray's march along the centerlines of its class's axis A (B is the other axis);
    // coordinates are sample coordinates (texel − ½).
    struct Walk {
        const Ray* ray;
        int axis, sign, cls, k0, count;
        float oA, oB, dB, invA, rise, tEnter, tExit;
        float tOf(int n) const {
            const float t = (float(k0 + sign * n) - oA) * invA;
            return std::clamp(t, tEnter, tExit);
        }
    };
    // The march's setup for a ray that enters the box (span = clip(ray)): false where the march
    // hands the ray to the exact walk over the span (outside φ_max or, exterior maps, an interior
    // origin: counted in fallbacks(); near-vertical rays). Shared with the packet march
    // (safety_cc/safety_cc_packet.h).
    bool setUp(const Ray& ray, const RayInterval& span, Walk& w) const;

    const Surface& surface() const { return *m_surface; }
    // How far above S a test position must be to count as above (float error).
    float margin() const { return m_margin; }

    // Rays traced by the exact walk because they are outside φ_max or (exterior maps) start
    // inside the box.
    uint64_t fallbacks() const { return m_fallbacks->load(std::memory_order_relaxed); }
    const Shape& shape() const { return m_shape; }
    const MarchOptions& options() const { return m_options; }

private:
    bool cellsHit(const Ray& ray, float ta, float tb, bool toExit, Hit& hit) const {
        return relief::cellsHit(*m_surface, ray, ta, tb, toExit, hit);  // surface/cell_walk.h
    }
    float sampleAB(int axis, int a, int b) const {
        return axis == 0 ? m_surface->sampleZ(a, b) : m_surface->sampleZ(b, a);
    }
    // Height of the ray above S at centerline offset n (S there = linear between two samples).
    float aboveAt(const Walk& w, int n, Hit& hit) const;
    int fetchStep(const Walk& w, int n, Hit& hit) const;
    bool finalHit(const Walk& w, int lo, int hi, Hit& hit) const;
    bool linearHit(const Walk& w, int lo, int hi, Hit& hit) const;

    std::shared_ptr<const Surface> m_surface;
    Shape m_shape;
    MarchOptions m_options;
    double m_tanPhi;
    float m_margin;
    std::shared_ptr<std::atomic<uint64_t>> m_fallbacks;
};

// ---- implementation ----

template <class Shape>
float SafetyTracer<Shape>::aboveAt(const Walk& w, int n, Hit& hit) const {
    const float t = w.tOf(n);
    const float b = w.oB + t * w.dB;
    const float fb = std::floor(b);
    const int a = w.k0 + w.sign * n, ib = int(fb);
    const float z0 = sampleAB(w.axis, a, ib), z1 = sampleAB(w.axis, a, ib + 1);
    hit.fetches += 2;
    return w.ray->origin.z + t * w.ray->direction.z - (z0 + (b - fb) * (z1 - z0));
}

template <class Shape>
int SafetyTracer<Shape>::fetchStep(const Walk& w, int n, Hit& hit) const {
    const Surface& s = *m_surface;
    const float t = w.tOf(n);
    int a = w.k0 + w.sign * n;
    int b = int(std::floor(w.oB + t * w.dB + 0.5f));
    const int lenA = w.axis == 0 ? s.width() : s.height();
    const int lenB = w.axis == 0 ? s.height() : s.width();
    if (s.edge() == EdgeMode::Repeat) {
        a %= lenA, b %= lenB;
        if (a < 0) a += lenA;
        if (b < 0) b += lenB;
    } else {
        a = std::clamp(a, 0, lenA - 1), b = std::clamp(b, 0, lenB - 1);
    }
    ++hit.fetches;
    const float z = w.ray->origin.z + t * w.ray->direction.z;
    const int step = w.axis == 0 ? m_shape.step(w.cls, a, b, z, w.rise)
                                 : m_shape.step(w.cls, b, a, z, w.rise);
    return m_options.positiveDistance ? std::max(step, 1) : step;
}

// The first hit between two adjacent centerlines: the reference's cell test, or (§7) the ray
// against S taken linear between the test positions there.
template <class Shape>
bool SafetyTracer<Shape>::finalHit(const Walk& w, int lo, int hi, Hit& hit) const {
    if (m_options.viewDependent) return linearHit(w, lo, hi, hit);
    return cellsHit(*w.ray, w.tOf(lo), w.tOf(hi), false, hit);
}

template <class Shape>
bool SafetyTracer<Shape>::linearHit(const Walk& w, int lo, int hi, Hit& hit) const {
    const float ta = w.tOf(lo), tb = w.tOf(hi);
    const float za = aboveAt(w, lo, hit), zb = aboveAt(w, hi, hit);
    float t0 = ta, z0 = za, t1 = tb, z1 = zb;
    const float ba = w.oB + ta * w.dB, bb = w.oB + tb * w.dB;
    if (std::floor(ba) != std::floor(bb)) {  // crosses a centerline of the other family
        const float c = std::max(std::floor(ba), std::floor(bb));
        const float tc = std::clamp((c - w.oB) / w.dB, std::min(ta, tb), std::max(ta, tb));
        const float a = (w.axis == 0 ? w.ray->origin.x : w.ray->origin.y) - 0.5f +
                        tc * (w.axis == 0 ? w.ray->direction.x : w.ray->direction.y);
        const float fa = std::floor(a);
        const float s0 = sampleAB(w.axis, int(fa), int(c));
        const float s1 = sampleAB(w.axis, int(fa) + 1, int(c));
        hit.fetches += 2;
        const float zc = w.ray->origin.z + tc * w.ray->direction.z - (s0 + (a - fa) * (s1 - s0));
        if (zc <= 0.0f) t1 = tc, z1 = zc; else t0 = tc, z0 = zc;
    }
    if (z0 <= 0.0f) {
        setHit(*w.ray, t0, hit);
        return true;
    }
    if (z1 > 0.0f) return false;
    setHit(*w.ray, t0 + (t1 - t0) * (z0 / (z0 - z1)), hit);
    return true;
}

template <class Shape>
bool SafetyTracer<Shape>::setUp(const Ray& ray, const RayInterval& span, Walk& w) const {
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    if ((!m_options.phiOutside && !rayWithinPhiMax(d, m_tanPhi)) ||
        (m_options.exterior && !originIsExterior(*m_surface, o))) {
        m_fallbacks->fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    w.ray = &ray;
    w.axis = std::abs(d.x) >= std::abs(d.y) ? 0 : 1;
    const float dA = w.axis == 0 ? d.x : d.y;
    w.sign = dA > 0.0f ? 1 : -1;
    w.cls = 2 * w.axis + (w.sign < 0 ? 1 : 0);
    w.oA = (w.axis == 0 ? o.x : o.y) - 0.5f;
    w.oB = (w.axis == 0 ? o.y : o.x) - 0.5f;
    w.dB = w.axis == 0 ? d.y : d.x;
    w.invA = 1.0f / dA;
    w.rise = d.z * std::abs(w.invA);
    w.tEnter = span.tEnter;
    w.tExit = span.tExit;
    const float aEnter = w.oA + span.tEnter * dA, aExit = w.oA + span.tExit * dA;
    const bool flat = dA == 0.0f || !std::isfinite(aEnter) || !std::isfinite(aExit);
    if (!flat) {
        w.k0 = int(w.sign > 0 ? std::ceil(aEnter) : std::floor(aEnter));
        const int kL = int(w.sign > 0 ? std::floor(aExit) : std::ceil(aExit));
        w.count = (kL - w.k0) * w.sign;
    }
    return !flat && w.count >= kMinCenterlines;  // near-vertical: a handful of cells
}

template <class Shape>
Hit SafetyTracer<Shape>::trace(const Ray& ray) const {
    Hit hit;
    const RayInterval span = m_surface->clip(ray);
    if (span.empty()) return hit;
    Walk w;
    if (!setUp(ray, span, w)) {
        cellsHit(ray, span.tEnter, span.tExit, true, hit);
        return hit;
    }
    if (cellsHit(ray, span.tEnter, w.tOf(0), false, hit)) return hit;  // up to the first one
    int n = 0;
    while (n < w.count) {
        if (m_options.maxSteps > 0 && hit.steps >= m_options.maxSteps) {
            setHit(ray, w.tOf(n), hit);  // approximate: the cursor
            return hit;
        }
        const int step = fetchStep(w, n, hit);
        if (step == 0) {  // the naive step (its cells are its steps), the other family's
                          // crossing tested exactly
            if (m_options.viewDependent ? linearHit(w, n, n + 1, hit)
                                        : cellsHit(ray, w.tOf(n), w.tOf(n + 1), false, hit))
                return hit;
            ++n;
            continue;
        }
        ++hit.steps;
        const int m = int(std::min<int64_t>(int64_t(n) + step, w.count));
        if (aboveAt(w, m, hit) > m_margin) {
            n = m;
            continue;
        }
        int lo = n, hi = m;
        while (hi - lo > 1) {
            ++hit.steps;
            const int mid = lo + (hi - lo) / 2;
            if (aboveAt(w, mid, hit) > m_margin) lo = mid; else hi = mid;
        }
        if (finalHit(w, lo, hi, hit)) return hit;
        n = hi;  // a false alarm within the margin: above S there after all
    }
    cellsHit(ray, w.tOf(w.count), span.tExit, true, hit);  // from the last centerline to the exit
    return hit;
}

}  // namespace relief::safety
