#pragma once
// qdm — quadratic displacement maps (cone + revolved parabola per texel), exact cell finish.
// This is variant 0 `safe` (the default); variant 1 `paper`, the map and tracer as published,
// is qdm_paper.h.
// Paper: M. Kiglics, G. Valasek, Cs. Bálint, R. Bán, "Quadratic Displacement Maps for Heightmap
//   Rendering" (Acta Cybernetica 2023): per texel a surface of revolution, a cone up to (a, b)
//   then the parabola y = −(x − c)² + b + (c − a)², that the heightfield never enters; the ray
//   steps to where it meets the surface of the texel it is in (Algorithm 1, Algorithm 2).
// Guarantee (qdm_map.h): texel (i, j) with footprint F = [i,i+1]×[j,j+1] stores (a, b, c, h),
//   h = max of S over F, such that S(q) ≤ h + f(dist(q, F)) for every q within `max-distance`
//   of F, where f is the NONDECREASING profile: s·x on [0, a] (s = b / a), the parabola on
//   [a, c], its top b + (c − a)² beyond c. For a marching position p in F, dist(q, F) ≤ |q − p|
//   and f is nondecreasing, so S(q) ≤ h + f(|q − p|): the surface of revolution about p bounds
//   S from any position in the texel, for rays in any direction (shadow rays included). Where
//   the top is below the highest point of S and max-distance is finite, a step is also cut at
//   max-distance of horizontal travel. When p.z < h or a step stalls (< kStall) the cell the
//   ray is in is tested exactly (firstHitInCell) and the ray moves to its exit, so the loop
//   ends on the reference's first hit unless `max-steps` stops it. Contract: conservative.
// Map: "qdm", 4 channels (a, b, c, h) per texel, W×H, float32, texel units (a, c horizontal
//   distances, b and h heights). Build (qdm_map.cpp): the max pyramid walked from F nearest
//   first, skipping nodes below the staircase of nearer points or below the profile reached so
//   far, until the cone is final; then branch and bound on c (nodes by the largest c_j they
//   could need); after 256 pops without a final cone, the cone by bisection on its slope
//   (a monotone "no steeper point within reach" test, pruned pyramid searches that skip the disc
//   already walked), warm-started from the previous texel's cone slope (rows in serpentine
//   order, so it is a neighbour's: probes at g(1 ± 0.5 %) bracket the answer, and the walk
//   before it is cut to 64 pops; neither changes the map); then the paper's search over the
//   points kept, by default on their upper convex bound (§4.1, Andrew's monotone chain). Output
//   equals the paper's all-cells builder (tests, both paths; warm start on/off bit for bit).
//   Build cost (2 threads, docs/qdm.md): peaks6 (gently rising, long staircases) 512² 4.7 s,
//   1024² 26 s CPU / 18–26 s wall (before the warm start 11.7 s and 69–74 s CPU); fbm 512² 1.2 s,
//   1024² 6.3 s CPU. Memory: the pyramid plus 16 bytes per texel.
// Steps = quadric steps + exact cell tests; fetches = 1 per quadric step + 4 per cell test.
// GLSL: qdm.glsl (+ qdm_map.glsl) mirrors trace: the same hits, t, steps and fetches.
// Departures: the apex is the max of S over the footprint and distances run from the
//   footprint (the published centre apex is not conservative on S between samples or off the
//   texel centre); m_uv is kept at the exact footprint-to-cell distances with corner maxima
//   instead of unit rings of samples; the parabola is used up to its top only (the descending
//   half bounds nothing from off-centre positions); the cone height limit is
//   height-ratio · max(S); no texture filtering; rays enter through any face.
#include <relief/surface/cell_cursor.h>
#include <relief/techniques/common/cone_maps.h>
#include <relief/techniques/common/safe_step_march.h>
#include <relief/techniques/qdm/qdm_map.h>

namespace relief {

struct QdmLimits {
    int maxSteps = 4096;
    float stall = 0.1f;  // a quadric step shorter than this hands over to an exact cell test
    // Steps stop this fraction short of the profile: a step can land exactly on S (flat
    // ground), and float rounding of t must not carry it past.
    float shorten = 1e-4f;
};

// The largest dt the profile (a, b, c) of an apex at height h allows from a position at height
// z (Algorithm 1 with the nondecreasing profile); `horizontal` = |d.xy|, `reach` = the horizontal
// distance the profile is valid for.
inline float quadricStep(const QdmTexel& q, float z, float horizontal, float dz, float reach) {
    const float h0 = z - q.h;
    const float slope = q.a > 0.0f ? q.b / q.a : 0.0f;
    const float closing = slope * horizontal - dz;
    const float tLine = closing > 0.0f ? h0 / closing : kInfinity;
    float dt;
    if (tLine * horizontal <= q.a) {
        dt = tLine;  // the line segment (alpha ≤ 1)
    } else {
        dt = parabolaStep(q, h0, horizontal, dz);
        if (!(dt * horizontal <= q.c)) {  // past the top: the flat part
            const float top = q.b + (q.c - q.a) * (q.c - q.a);
            dt = dz < 0.0f ? (top - h0) / dz : kInfinity;
        }
    }
    return horizontal > 0.0f ? std::min(dt, reach / horizontal) : dt;
}

// [ta, tb] of cell (ci, cj) along the ray, computed as ExactTracer computes it (boundaries from
// the cell index times 1/d), so that the finish reproduces the reference's rounding. The ray is
// above S up to the current position, so starting the test at the cell's entry is safe; a
// landing a hair from S (flat ground, grazing rays) then gives the reference's t, not one
// rounded past it.
inline vec2 referenceSpan(const Ray& ray, int ci, int cj, const RayInterval& span) {
    auto boundary = [](int cell, float o, float d, bool entering) {
        if (d == 0.0f) return entering ? -kInfinity : kInfinity;
        return (float(cell) + ((d > 0.0f) != entering ? 1.5f : 0.5f) - o) * (1.0f / d);
    };
    const vec3 &o = ray.origin, &d = ray.direction;
    const float ta = std::max({span.tEnter, boundary(ci, o.x, d.x, true),
                               boundary(cj, o.y, d.y, true)});
    const float tb = std::min({boundary(ci, o.x, d.x, false), boundary(cj, o.y, d.y, false),
                               span.tExit});
    return {ta, std::max(ta, tb)};
}

class QdmTracer {
public:
    QdmTracer(std::shared_ptr<const Surface> surface, std::shared_ptr<const QdmMap> map,
              QdmLimits limits)
        : m_surface(std::move(surface)), m_map(std::move(map)), m_limits(limits) {}

    Hit trace(const Ray& ray) const;

private:
    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const QdmMap> m_map;
    QdmLimits m_limits;
};

inline Hit QdmTracer::trace(const Ray& ray) const {
    const vec3& d = ray.direction;
    const auto quadricSafeStep = [&](const vec3& p, float horizontal, Hit& hit) {
        const QdmTexel q = m_map->at(p.x, p.y);
        ++hit.fetches;
        // On the apex height the ray may touch S: the cell test decides.
        return p.z > q.h ? (1.0f - m_limits.shorten) *
                               quadricStep(q, p.z, horizontal, d.z, m_map->reach(q))
                         : -kInfinity;
    };
    // Exact: the cell the ray is in, from where it entered it to where it leaves it.
    const auto referenceCell = [&](const CellSpan& cell, float t, const RayInterval& span) {
        const vec2 cellSpan = referenceSpan(ray, cell.ci, cell.cj, span);
        return CellRangeAlong{cellSpan.x, cellSpan.y, cellSpan.y > t ? cellSpan.y : cell.tb};
    };
    return safeStepMarch(*m_surface, ray, {m_limits.maxSteps, m_limits.stall}, quadricSafeStep,
                         referenceCell);
}

inline constexpr ParamSpec kQdmParams[] = {
    {"max-steps", 4096, 1, 1e9, true,
     "iteration cap (quadric steps + exact cell tests); the default lets grazing rays converge",
     ParamRole::IterationCap},
    {"height-ratio", 0.2, 0.0, 1.0, false,
     "cone part height limit as a fraction of the highest point of S (paper: 0.2 best)",
     ParamRole::MapShape},
    {"max-distance", 0, 0, 1e6, false,
     "horizontal reach of the parabola search in texels; 0 = unlimited (whole map)",
     ParamRole::MapShape},
    {"convex-bound", 1, 0, 1, true,
     "1 = fit the parabola to the upper convex bound's vertices (paper §4.1), 0 = all points",
     ParamRole::MapShape},
    {"variant", 0, 0, 1, true,
     "0 = safe (footprint profile, exact cell finish), 1 = paper (the published map and "
     "Algorithm 1, qdm_paper.h)",
     ParamRole::Variant},
};
Result<std::unique_ptr<Tracer>> createQdm(const TechniqueInput& input);
Result<TechniqueMaps> buildQdmMaps(const TechniqueInput& input);

}  // namespace relief
