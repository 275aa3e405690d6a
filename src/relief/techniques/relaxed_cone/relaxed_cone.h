#pragma once
// relaxed-cone — relaxed cone stepping then binary refinement.
// Paper: F. Policarpo & M. M. Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3
//   ch. 18 (2007): cones that may pierce the surface but never let a ray enter the solid twice
//   inside them; after `max-steps` cone steps a binary search between the last two positions
//   finds the hit.
// Guarantee: the published map (cone_maps.h FaithfulRelaxed): only rays from the box top above
//   the apex are considered. Rays entering the box elsewhere, or reaching a marching position
//   after a step, can cross S twice inside a cone (safety shapes §3, Fig. 4): a thin wall is
//   stepped over. Approximate.
//   There is no strict-cone variant: a relaxed cone that keeps the single-crossing property for
//   every ray reaching a marching position from anywhere above S is a strict cone (safety shapes
//   §3, Fig. 6(a)), i.e. the safe map of `cone`, and with an exact finish it would be `cone`
//   (variant 0) under another name; use `cone` for the conservative form.
// Shadow rays (d.z ≥ 0): cones built for descending rays say nothing about them; they go to the
//   reference walk (surface/cell_walk.h, as ExactTracer), so they are exact.
// Map: "cones", as `cone` (same encodings, recorded as variant 1). Build: one ray walk (exact
//   cell exits) per sample B above the apex whose strict ratio is below the cone found so far, stopped
//   where the ratio reaches it, samples found through the max pyramid and the neighbour's
//   guess (cone_maps.h); equal to the Θ(N⁴) brute force to the bit. 1024² on two threads:
//   fbm 69 s CPU (≈ 35 s wall idle; 102 s under load), the SRTM window 4.6 s CPU
//   (docs/cones.md; the published preprocess is reported at about 8 hours); ≈ 10–13× per
//   doubling of the side on fbm.
// Steps = cone steps + binary steps; fetches = 1 per cone step + 4 per S evaluation.
// Departures: the binary search evaluates S exactly (not a bilinear fetch); rays enter through
//   any face; a ray entering below S hits at entry; the map is fetched nearest-texel.
#include <relief/surface/cell_cursor.h>
#include <relief/surface/cell_walk.h>
#include <relief/techniques/common/cone_maps.h>

namespace relief {

struct RelaxedLimits {
    int maxSteps = 15;
    int binarySteps = 8;
};

class RelaxedConeTracer {
public:
    RelaxedConeTracer(std::shared_ptr<const Surface> surface, std::shared_ptr<const ConeMap> map,
                      RelaxedLimits limits)
        : m_surface(std::move(surface)), m_map(std::move(map)), m_limits(limits) {}

    Hit trace(const Ray& ray) const;

private:
    Hit refine(const Ray& ray, float lo, float hi, float tExit, Hit hit) const;

    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const ConeMap> m_map;
    RelaxedLimits m_limits;
};

inline Hit RelaxedConeTracer::trace(const Ray& ray) const {
    const vec3& d = ray.direction;
    const Surface& s = *m_surface;
    Hit hit;
    const RayInterval span = s.clip(ray);
    if (span.empty()) return hit;
    if (d.z >= 0.0f) {  // the reference walk (ExactTracer::trace)
        cellsHit(s, ray, span.tEnter, span.tExit, true, hit);
        return hit;
    }
    const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
    float t = span.tEnter, tPrev = t;
    const vec3 entry = ray.at(t);
    hit.fetches += 4;
    if (entry.z <= s.heightAt(entry.x, entry.y)) return hitAt(ray, t, hit);  // side wall
    while (hit.steps < m_limits.maxSteps) {
        ++hit.steps;
        const vec3 p = ray.at(t);
        const vec2 cone = m_map->at(p.x, p.y);
        ++hit.fetches;
        const float dt = p.z > cone.x ? coneStep(p.z, cone.x, cone.y, horizontal, d.z) : 0.0f;
        if (!(dt > 0.0f)) break;
        tPrev = t;
        t = std::min(t + dt, span.tExit);
        if (t >= span.tExit) break;
    }
    return refine(ray, tPrev, t, span.tExit, hit);
}

inline Hit RelaxedConeTracer::refine(const Ray& ray, float lo, float hi, float tExit,
                                     Hit hit) const {
    const Surface& s = *m_surface;
    auto below = [&](float t) {
        hit.fetches += 4;
        const vec3 q = ray.at(t);
        return q.z <= s.heightAt(q.x, q.y);
    };
    if (!below(hi)) {
        if (hi < tExit) return hitAt(ray, hi, hit);  // not converged: the last position
        return exitsThroughFloor(s, ray, tExit) ? hitAt(ray, tExit, hit) : hit;
    }
    for (int k = 0; k < m_limits.binarySteps; ++k) {
        ++hit.steps;
        const float mid = 0.5f * (lo + hi);
        if (below(mid)) hi = mid; else lo = mid;
    }
    return hitAt(ray, lo, hit);  // the last position above S
}

inline constexpr ParamSpec kRelaxedConeParams[] = {
    {"max-steps", 15, 1, 4096, true, "relaxed cone steps (GPU Gems 3 listing: 15)",
     ParamRole::IterationCap},
    {"binary-steps", 8, 0, 64, true, "binary refinement steps"},
    {"bits", 32, 8, 32, true, "map encoding: 32 (float), 16 or 8 (codes rounded to the safe side)",
     ParamRole::Encoding},
    {"sqrt", 0, 0, 1, true, "store sqrt of the cone ratio (finer codes for narrow cones)",
     ParamRole::Encoding},
};
Result<std::unique_ptr<Tracer>> createRelaxedCone(const TechniqueInput& input);
Result<TechniqueMaps> buildRelaxedConeMaps(const TechniqueInput& input);
// The row's check: the parameters, and input.maps (decoded, then dropped) when given.
Status checkRelaxedCone(const TechniqueInput& input);

}  // namespace relief
