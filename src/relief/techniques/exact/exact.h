#pragma once
// exact — the reference tracer (DESIGN §3).
// Paper: the naive accurate algorithm of Baboud & Décoret (2006) after Amanatides & Woo (1987), as
//   in "Precomputed Safety Shapes", §5.2.1: walk the cells the ray crosses, test both triangles.
// Guarantee: exact on S (first hit, |Δt| at float precision); validated against Embree.
// Map: none (reads the heightfield). Build cost: none.
// Steps = cells visited; fetches = corner samples read (4 per cell).
// Departure: the ray is clipped to the box first (entry through any face); a ray whose entry
// point lies below S hits the solid at the entry (DESIGN §1), which the first cell test reports.
#include <relief/surface/cell_intersect.h>
#include <relief/techniques/technique.h>

namespace relief {

class ExactTracer {
public:
    explicit ExactTracer(std::shared_ptr<const Surface> surface) : m_surface(std::move(surface)) {}

    Hit trace(const Ray& ray) const;

private:
    std::shared_ptr<const Surface> m_surface;
};

inline Hit ExactTracer::trace(const Ray& ray) const {
    const Surface& s = *m_surface;
    Hit hit;
    const RayInterval span = s.clip(ray);
    if (span.empty()) return hit;
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    const vec3 entry = ray.at(span.tEnter);
    int ci = s.cellOfX(entry.x), cj = s.cellOfY(entry.y);
    const int stepX = d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0);
    const int stepY = d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0);
    const float invX = 1.0f / d.x, invY = 1.0f / d.y;
    const bool clamp = s.edge() == EdgeMode::Clamp;
    float ta = span.tEnter;
    for (;;) {
        // Boundaries from the cell index each time: no drift from accumulated increments.
        const float tx = stepX == 0 ? kInfinity : (float(ci) + (stepX > 0 ? 1.5f : 0.5f) - o.x) * invX;
        const float ty = stepY == 0 ? kInfinity : (float(cj) + (stepY > 0 ? 1.5f : 0.5f) - o.y) * invY;
        const float tb = std::max(ta, std::min({tx, ty, span.tExit}));
        ++hit.steps;
        hit.fetches += 4;
        const float t = firstHitInCell(s.cellPlanes(ci, cj), ray, ci, cj, ta, tb);
        if (t <= tb) {
            hit.hit = true;
            hit.t = t;
            hit.position = ray.at(t);
            return hit;
        }
        if (tb >= span.tExit) {
            // Leaving through the bottom face means reaching z = 0 ≤ S: S is there. Where samples
            // are 0 the floor lies in that face and rounding can leave the cell test a hair
            // above it at tExit, so the test alone misses such hits.
            const float zExit = o.z + span.tExit * d.z;
            const float zRounding = 4.0f * std::numeric_limits<float>::epsilon() *
                                    (std::abs(o.z) + s.depth());
            if (d.z < 0.0f && zExit <= zRounding) {
                hit.hit = true;
                hit.t = span.tExit;
                hit.position = ray.at(span.tExit);
            }
            return hit;
        }
        if (tx <= ty) ci += stepX; else cj += stepY;
        if (clamp && (ci < -1 || ci > s.width() - 1 || cj < -1 || cj > s.height() - 1)) return hit;
        ta = tb;
    }
}

}  // namespace relief

namespace relief {
inline constexpr ParamSpec kExactParams[] = {
    {"max-steps", 0, 0, 1e9, true, "cell cap (0 = none; the reference never stops early)",
     ParamRole::IterationCap},
};
Result<std::unique_ptr<Tracer>> createExact(const TechniqueInput& input);
// The reference never stops early: a cap (max-steps) is refused.
Status checkExact(const TechniqueInput& input);
}  // namespace relief
