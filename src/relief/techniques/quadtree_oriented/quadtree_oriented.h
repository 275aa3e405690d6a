#pragma once
// quadtree-oriented — quadtree relief mapping with oriented nodes.
// Paper: Schroders & van Gulik, "Quadtree Relief Mapping" (GH 2006), §5: "instead of the
//   horizontal plane, an oriented plane that rests on top of the surface could also be used ...
//   four height values: one for each corner", stored in RGBA.
// Guarantee: exact on S (same hit/miss as `exact`, |Δt| ≤ 1e-3); approximate with max-steps > 0.
//   Why the plane P of a node bounds S over the node: P is fitted so that P ≥ h at every sample
//   (vertex) of the node's cells. S is linear on each triangle of a cell (S = max of the two
//   planes, and on each triangle of the lower-diagonal split the max is that triangle's plane),
//   so P - S is linear on each triangle and takes its minimum at a triangle vertex, where
//   P - S = P - h ≥ 0. The cells (border strips included) cover the node, hence P ≥ S on the
//   whole node; min(P, flat maximum) ≥ S as well, and the walk skips only what lies above it.
// Map (levels ≥ 1, oriented_pyramid.h): per node RGBA = (c00, c10, c01, zmax): the plane's heights
//   at three corners of the node's nominal 2^L square (the fourth is c10 + c01 - c00) and the
//   flat maximum; level 0 reads the flat max pyramid of `quadtree`. 16 bytes per node,
//   ≈ 16/3 (W+1)(H+1) bytes plus the max pyramid.
//   Fit: slope = difference of the children's maxima over the distance between their centres
//   (a plane leaning like the upper envelope), offset = the lowest that clears every vertex of
//   the node (searched in float), plus a 2e-6 relative margin that covers every rounding.
//   Build: O(WH log(WH)) (each level reads every vertex once): 0.2–0.4 s at 4096², ≈ 1 s at
//   8192² on two cores.
// Walk: common/pyramid_walk.h with the `quadtree` default policy (jump to the neighbour, up one
//   level on entering a new parent). Per node: the flat max as a fast pre-test, then the plane:
//   the cursor moves to the first point below both, or the node is skipped.
// Steps = nodes and cells tested; fetches = node reads (one RGBA each) + 4 per cell test.
// Departures: a plane (3 degrees of freedom) rather than 4 free corner heights (a bilinear
//   bound would need a quadratic per node); the fourth channel holds the flat max instead of
//   the redundant corner. The finest level (one cell) keeps the flat max: the exact cell test
//   follows at once, so a plane there would only cost memory.
#include <relief/techniques/common/pyramid_walk.h>
#include <relief/techniques/quadtree_oriented/oriented_pyramid.h>
#include <relief/techniques/technique.h>

#include <memory>

namespace relief {

inline constexpr auto kInverseSides = [] {
    std::array<float, PyramidLayout::kMaxLevels> inverse{};
    for (int level = 0; level < PyramidLayout::kMaxLevels; ++level)
        inverse[size_t(level)] = 1.0f / float(1 << level);
    return inverse;
}();

// First t in [t, tOut] where the ray is on or below the node's plane, given that it is below the
// node's max from t on (descending) or at t (rising); > tOut when there is none.
inline float enterBelowPlane(const OrientedNode& n, const NodeBox& b, const WalkRay& r, float t,
                             float tOut) {
    const float scale = kInverseSides[size_t(b.level)];
    const float sx = (n.c10 - n.c00) * scale, sy = (n.c01 - n.c00) * scale;
    const vec3 p = r.at(t);
    const float above = p.z - (n.c00 + sx * (p.x - b.x0()) + sy * (p.y - b.y0())) - r.slack;
    if (above <= 0.0f) return t;
    const float rate = r.d.z - sx * r.d.x - sy * r.d.y;  // d(above)/dt
    if (rate >= 0.0f) return kInfinity;
    const float tPlane = t - above / rate;
    if (tPlane > tOut) return kInfinity;
    if (r.d.z > 0.0f && r.o.z + tPlane * r.d.z > n.zmax + r.slack) return kInfinity;
    return tPlane;
}

class OrientedBound {
public:
    OrientedBound(const MaxPyramid& maxima, const OrientedPyramid& planes)
        : m_maxima(&maxima), m_planes(&planes) {}
    float enter(const NodeBox& b, const WalkRay& r, float t, float tOut) const {
        if (b.level == 0) return enterBelow(m_maxima->at(0, b.nx, b.ny) + r.slack, r, t, tOut);
        const OrientedNode& n = m_planes->at(b.level, b.nx, b.ny);
        const float tIn = enterBelow(n.zmax + r.slack, r, t, tOut);
        if (tIn > tOut) return tIn;
        return enterBelowPlane(n, b, r, tIn, tOut);
    }

private:
    const MaxPyramid* m_maxima;
    const OrientedPyramid* m_planes;
};

// The maps of quadtree-oriented: the flat pyramid (its level 0 is read; it can be shared with
// `quadtree` and `maxmip`) and the oriented one.
struct OrientedMaps {
    std::shared_ptr<const MaxPyramid> maxima;
    OrientedPyramid planes;

    explicit OrientedMaps(const Surface& surface);
    OrientedMaps(const VertexGrid& vertices, std::shared_ptr<const MaxPyramid> maxima);
    OrientedMaps(std::shared_ptr<const MaxPyramid> maxima, OrientedPyramid planes);
};

class QuadtreeOrientedTracer {
public:
    QuadtreeOrientedTracer(std::shared_ptr<const Surface> surface,
                           std::shared_ptr<const OrientedMaps> maps, WalkLimits limits)
        : m_surface(std::move(surface)), m_maps(std::move(maps)), m_limits(limits) {}

    Hit trace(const Ray& ray) const {
        const OrientedBound bound(*m_maps->maxima, m_maps->planes);
        return walkPyramid<Ascent::Parent>(*m_surface, m_maps->maxima->layout(), bound, ray,
                                           m_limits);
    }
    const OrientedMaps& maps() const { return *m_maps; }

private:
    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const OrientedMaps> m_maps;
    WalkLimits m_limits;
};

inline constexpr ParamSpec kQuadtreeOrientedParams[] = {
    {"max-steps", 0, 0, 1e9, true, "iteration cap (0 = none, exact); N > 0 is approximate",
     ParamRole::IterationCap},
};
Result<std::unique_ptr<Tracer>> createQuadtreeOriented(const TechniqueInput& input);
// Both pyramids as baked maps ("level<L>" and "oriented<L>"; quadtree_oriented_maps.cpp), and
// the maps to trace with: from input.maps (checked) or built now.
Result<TechniqueMaps> buildQuadtreeOrientedMaps(const TechniqueInput& input);
Result<std::shared_ptr<const OrientedMaps>> orientedMapsFor(const TechniqueInput& input);

}  // namespace relief
