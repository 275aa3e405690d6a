#pragma once
// exact — the reference tracer (DESIGN §3).
// Paper: the naive accurate algorithm of Baboud & Décoret (2006) after Amanatides & Woo (1987), as
//   in "Precomputed Safety Shapes", §5.2.1: walk the cells the ray crosses, test both triangles.
// Guarantee: exact on S (first hit, |Δt| at float precision); validated against Embree.
// Map: none (reads the heightfield). Build cost: none.
// Steps = cells visited; fetches = corner samples read (4 per cell).
// Departure: the ray is clipped to the box first (entry through any face); a ray whose entry
// point lies below S hits the solid at the entry (DESIGN §1), which the first cell test reports.
// The walk itself is the surface's (surface/cell_walk.h), shared with the tracers' exact parts;
// batches go through its SIMD packet twin (surface/cell_walk_packet.h, the same hits bit for bit)
// unless the ISA is baseline or RELIEF_PACKETS=0.
#include <relief/surface/cell_walk.h>
#include <relief/techniques/technique.h>

namespace relief {

class ExactTracer {
public:
    explicit ExactTracer(std::shared_ptr<const Surface> surface) : m_surface(std::move(surface)) {}

    Hit trace(const Ray& ray) const;
    const Surface& surface() const { return *m_surface; }

private:
    std::shared_ptr<const Surface> m_surface;
};

inline Hit ExactTracer::trace(const Ray& ray) const {
    Hit hit;
    const RayInterval span = m_surface->clip(ray);
    if (!span.empty()) cellsHit(*m_surface, ray, span.tEnter, span.tExit, true, hit);
    return hit;
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
