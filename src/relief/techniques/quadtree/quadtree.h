#pragma once
// quadtree — quadtree relief mapping.
// Paper: Schroders & van Gulik, "Quadtree Relief Mapping" (GH 2006), Algorithm 1: a cursor moves
//   along the ray through a max quadtree; at each node the ray meets the horizontal plane at the
//   node's maximum: inside the node → move the cursor there and descend; outside → move it to
//   the node's boundary and continue in the neighbouring node at the same level.
// Guarantee: exact on S (same hit/miss as `exact`, |Δt| ≤ 1e-3) with the default parameters.
//   Skipped nodes lie above their maximum, which bounds S (max_pyramid.h); a level-0 node the ray
//   dips into gets the reference's two-triangle cell test, and when that finds nothing the walk
//   goes on to the next cell. With max-steps > 0 or box-surface = 1, 2 it is approximate on S;
//   box-surface = 2 is exact on its own surface, the texel boxes (surface/texel_boxes.h).
// Map: the max pyramid (max_pyramid.h): one float per node, ≈ 4/3 (W+1)(H+1) floats; built in
//   O(WH), ≈ 0.1 s at 4096² on two cores. bits = 16 / 8 store the maxima as codes rounded up:
//   exact still (the cell test reads the heights); box-surface = 1 stops at the rounded boxes.
// Steps = nodes and cells tested; fetches = pyramid reads + 4 per cell test.
// Departures from the paper:
//   - S instead of texel boxes: the finest level holds one cell's corner maximum, and the walk
//     finishes with the exact cell test. `box-surface` = 1 stops at level 0 on those cell boxes
//     (the paper's stop, not its surface); `box-surface` = 2 is the paper's surface: the texel
//     pyramid (sample heights, texel (i, j) = [i, i+1] × [j, j+1] centred on its sample), its
//     level-0 box the hit (CPU only; baked maps record box-surface = 2).
//   - The paper never goes up (ascend = 0, its Algorithm 1 verbatim). Once the exact cell test
//     can fail, that walks on cell by cell; the default (ascend = 1) goes up one level when the
//     neighbour lies in another parent, still jumping to neighbours rather than to the common
//     ancestor (that is `maxmip`).
//   - The neighbour is an integer index step, not the cursor plus an offset delta; rays enter
//     through any face (Surface::clip), go up as well as down (shadow rays), and a ray entering
//     below S through a side wall hits it at the entry.
//   - max-steps = 0 (the default) is the dynamic loop; N > 0 is the paper's fixed loop: after N
//     iterations it reports a hit at the cursor.
//   - The dynamic loop with ascend = 1 on S starts at the smallest node over the ray's footprint
//     instead of the root (startCursor: the same hits, never more steps); Algorithm 1, the fixed
//     loop and the box surfaces start at the root, as the paper does.
// Packets: the defaults (ascend 1, max-steps 0, box-surface 0, bits 32) trace a batch 8 or 16 rays
//   at a time in SIMD lanes (common/pyramid_walk_packet.h), bit-identical to the scalar walk;
//   RELIEF_PACKETS=0 in the environment, or the tracers' ISA baseline (RELIEF_ISA / --isa,
//   core/isa.h), keeps the scalar walk (A/B).
#include <relief/techniques/common/pyramid_walk.h>
#include <relief/techniques/technique.h>

#include <memory>

namespace relief {

class QuadtreeTracer {
public:
    QuadtreeTracer(std::shared_ptr<const Surface> surface,
                   std::shared_ptr<const MaxPyramid> pyramid, Ascent ascent, WalkLimits limits)
        : m_surface(std::move(surface)),
          m_pyramid(std::move(pyramid)),
          m_ascent(ascent),
          m_limits(limits) {}

    Hit trace(const Ray& ray) const {
        const MaxBound bound(*m_pyramid);
        const PyramidLayout& layout = m_pyramid->layout();
        if (m_ascent == Ascent::None)
            return walkPyramid<Ascent::None>(*m_surface, layout, bound, ray, m_limits);
        return walkPyramid<Ascent::Parent>(*m_surface, layout, bound, ray, m_limits);
    }
    const MaxPyramid& pyramid() const { return *m_pyramid; }
    const Surface& surface() const { return *m_surface; }

private:
    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const MaxPyramid> m_pyramid;
    Ascent m_ascent;
    WalkLimits m_limits;
};

inline constexpr ParamSpec kQuadtreeParams[] = {
    {"max-steps", 0, 0, 1e9, true,
     "iteration cap (0 = none, exact); N > 0: the paper's fixed loop, approximate",
     ParamRole::IterationCap},
    {"ascend", 1, 0, 1, true,
     "after a jump: 0 = stay at the level (the paper), 1 = up one level on entering a new parent",
     ParamRole::Variant},
    kBoxSurfaceParam,
    {"bits", 32, 8, 32, true,
     "pyramid maxima: 32 (float), 16 or 8 (codes of D rounded up; the tracer stays exact; "
     "box-surface=2 needs 32)",
     ParamRole::Encoding},
};
Result<std::unique_ptr<Tracer>> createQuadtree(const TechniqueInput& input);
Result<TechniqueMaps> buildQuadtreeMaps(const TechniqueInput& input);

}  // namespace relief
