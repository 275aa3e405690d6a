#pragma once
// cone — conservative cone step mapping with an exact finish.
// Paper: W. Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm"
//   (2006): per texel the widest upward cone, apex on the surface, that the heightfield never
//   enters; the ray steps to where it leaves the cone of the texel it is in.
// Guarantee (variant 0 `safe`, the default, cone_maps.h SafeStrict): each texel (i, j) stores
//   (a, c) such that S never enters the frustum K = {dist(xy, [i,i+1]×[j,j+1]) ≤ c·(z − a)}
//   with a = max of S over the footprint. Every marching position p inside the footprint with
//   p.z ≥ a is in K and K is convex, so the step to K's boundary (coneStep) never passes S,
//   from any position in the texel, for rays in any direction (upward ones included). Where
//   p.z < a or the step stalls (< kStall), the tracer tests the cell the ray is in exactly
//   (firstHitInCell) and moves to its exit: the result is the reference's first hit whenever
//   the loop ends before `max-steps`. Contract: conservative.
//   Variant 1 `faithful` (FaithfulStrict): the published map, apex at the sample, distances
//   between sample centres. S between samples and positions off the texel centre can enter the
//   cone: approximate (measured in cone_test.cpp and docs/cones.md).
// Map: "cones", 2 channels (a, c) per texel, W×H; float32 or 16/8-bit codes rounded to the safe
//   side (cone_maps.h). Build: pyramid-pruned search (cone_maps.h), O(WH · nodes near the
//   cone), parallel over rows, 8 bytes per texel plus the max pyramid; equal to the Θ(N⁴) brute
//   force to the bit. 1024² fbm on two threads: safe 1.9 s wall / 1.4 s CPU, faithful 5.2 s /
//   3.5 s on a loaded machine (docs/cones.md; about 4.5× per doubling of the side).
// Steps = cone steps + exact cell tests; fetches = 1 per cone step + 4 per cell test.
// Batches (clamp mode) go through the SIMD packet march (cone_packet.h), the same hits bit for
// bit, unless the ISA is baseline or RELIEF_PACKETS=0.
// Departures: the footprint frustum (rather than a point apex) and the exact finish make the
//   method conservative on S; the map is fetched nearest-texel (no interpolation between
//   texels, which would not be conservative); rays enter through any face (Surface::clip).
#include <relief/surface/cell_cursor.h>
#include <relief/techniques/common/cone_maps.h>
#include <relief/techniques/common/safe_step_march.h>

namespace relief {

struct ConeLimits {
    int maxSteps = 4096;
    // A cone step shorter than this (texel units along t) hands over to an exact cell test.
    float stall = 0.1f;
};

// What cone/cone.glsl and the common/cone_maps.glsl it requires read (the row's glslConstants).
inline constexpr GlslConstant kConeGlslConstants[] = {
    {"kConeDecodeMargin", double(kConeDecodeMargin), false},
    {"kConeStall", double(ConeLimits{}.stall), false},
};

class ConeTracer {
public:
    ConeTracer(std::shared_ptr<const Surface> surface, std::shared_ptr<const ConeMap> map,
               ConeLimits limits)
        : m_surface(std::move(surface)), m_map(std::move(map)), m_limits(limits) {}

    Hit trace(const Ray& ray) const;
    const Surface& surface() const { return *m_surface; }
    const ConeMap& map() const { return *m_map; }
    ConeLimits limits() const { return m_limits; }

private:
    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const ConeMap> m_map;
    ConeLimits m_limits;
};

inline Hit ConeTracer::trace(const Ray& ray) const {
    const vec3& d = ray.direction;
    const auto coneSafeStep = [&](const vec3& p, float horizontal, Hit& hit) {
        const vec2 cone = m_map->at(p.x, p.y);
        ++hit.fetches;
        // On the floor (z ≤ 0) the cell test decides: a ray entering from below meets the solid
        // there even where a = 0 (depth 0, or a flat floor), which a cone step would skip.
        return p.z >= cone.x && p.z > 0.0f ? coneStep(p.z, cone.x, cone.y, horizontal, d.z)
                                           : -kInfinity;
    };
    // Exact: the cell the ray is in, up to where it leaves it.
    const auto wholeCell = [](const CellSpan& cell, float t, const RayInterval&) {
        return CellRangeAlong{t, cell.tb, cell.tb};
    };
    return safeStepMarch(*m_surface, ray, {m_limits.maxSteps, m_limits.stall}, coneSafeStep,
                         wholeCell);
}

inline constexpr ParamSpec kConeParams[] = {
    {"max-steps", 4096, 1, 1e9, true,
     "iteration cap (cone steps + exact cell tests); the default lets grazing rays converge",
     ParamRole::IterationCap},
    {"variant", 0, 0, 1, true, "0 = safe (footprint frustum, conservative), 1 = faithful (Dummer)",
     ParamRole::Variant},
    {"bits", 32, 8, 32, true, "map encoding: 32 (float), 16 or 8 (codes rounded to the safe side)",
     ParamRole::Encoding},
    {"sqrt", 0, 0, 1, true, "store sqrt of the cone ratio (finer codes for narrow cones)",
     ParamRole::Encoding},
};
Result<std::unique_ptr<Tracer>> createCone(const TechniqueInput& input);
Result<TechniqueMaps> buildConeMaps(const TechniqueInput& input);
// The row's check: the parameters, and input.maps (decoded, then dropped) when given.
Status checkCone(const TechniqueInput& input);

}  // namespace relief
