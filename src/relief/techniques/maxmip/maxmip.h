#pragma once
// maxmip — maximum mipmaps traversed like a ray tracer.
// Paper: Tevs, Ihrke & Seidel, "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height
//   Field Rendering" (I3D 2008): a hierarchical walk of a max pyramid; a node is skipped when
//   the ray passes above its maximum, and after leaving a node the walk ascends to the common
//   ancestor of the node and its neighbour before descending again.
// Guarantee: exact on S (same hit/miss as `exact`, |Δt| ≤ 1e-3); with max-steps > 0 it is
//   approximate (a hit at the cursor when the cap is reached); box-surface = 1, 2 as quadtree's
//   (2: the paper-era texel boxes, exact on them, approximate on S, CPU only).
// Map: the max pyramid shared with `quadtree` (common/max_pyramid.h): one float per node,
//   ≈ 4/3 (W+1)(H+1) floats, O(WH) build; bits = 16 / 8 store the maxima as codes rounded up
//   (exact still: the cell test reads the heights). The walk is common/pyramid_walk.h with the
//   Ancestor policy; only the policy differs from `quadtree`.
// Steps = nodes and cells tested; fetches = pyramid reads + 4 per cell test.
// Departures: Tevs et al. bound a texel's bilinear patch by its max and intersect the patch;
//   here the finest level bounds a cell of S (its corner maximum) and the cell is intersected
//   with the reference's two-triangle test. The walk ascends to the child of the common
//   ancestor that holds the neighbour (the ancestor itself was already entered); crossing the
//   tile seam in repeat mode restarts at the root of the next tile. Uncapped on S, the walk
//   starts at the smallest node over the ray's footprint, not the root (startCursor: the same
//   hits, never more steps).
// Packets: the defaults (max-steps 0, box-surface 0, bits 32) trace a batch in SIMD lanes
//   (common/pyramid_walk_packet.h), bit-identical; RELIEF_PACKETS=0 keeps the scalar walk.
#include <relief/techniques/common/pyramid_walk.h>
#include <relief/techniques/technique.h>

#include <memory>

namespace relief {

class MaxmipTracer {
public:
    MaxmipTracer(std::shared_ptr<const Surface> surface, std::shared_ptr<const MaxPyramid> pyramid,
                 WalkLimits limits)
        : m_surface(std::move(surface)), m_pyramid(std::move(pyramid)), m_limits(limits) {}

    Hit trace(const Ray& ray) const {
        return walkPyramid<Ascent::Ancestor>(*m_surface, m_pyramid->layout(), MaxBound(*m_pyramid),
                                             ray, m_limits);
    }

    const MaxPyramid& pyramid() const { return *m_pyramid; }
    const Surface& surface() const { return *m_surface; }

private:
    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const MaxPyramid> m_pyramid;
    WalkLimits m_limits;
};

inline constexpr ParamSpec kMaxmipParams[] = {
    {"max-steps", 0, 0, 1e9, true, "iteration cap (0 = none, exact); N > 0 is approximate",
     ParamRole::IterationCap},
    kBoxSurfaceParam,
    {"bits", 32, 8, 32, true,
     "pyramid maxima: 32 (float), 16 or 8 (codes of D rounded up; the tracer stays exact; "
     "box-surface=2 needs 32)",
     ParamRole::Encoding},
};
Result<std::unique_ptr<Tracer>> createMaxmip(const TechniqueInput& input);
Result<TechniqueMaps> buildMaxmipMaps(const TechniqueInput& input);  // maxmip_maps.cpp

}  // namespace relief
