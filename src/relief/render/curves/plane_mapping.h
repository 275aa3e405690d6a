#pragma once
// Plane ↔ view plane by 3×3 projective matrices (Fourquet et al. 2008, §5.1).
// With the eye at the origin, a point of the base plane z = 0 is S·(s, t, 1) with
// S = [î_s ĵ_s O_s − eye] and a view-plane point is V·(u, v, 1) with V = [î_v ĵ_v O_v − eye]
// (columns in world coordinates; (u, v) in pixels, (0,0) = top-left). Both name the same eye
// ray, so (u, v, 1) ∝ Q·(s, t, 1) with Q = V⁻¹S, and (s, t, 1) ∝ Q'·(u, v, 1) with Q' = S⁻¹V.
#include <relief/render/curves/view_frame.h>

#include <glm/glm.hpp>

namespace relief::curves {

class PlaneMapping {
public:
    explicit PlaneMapping(const ViewFrame& view);

    dvec2 toView(const dvec2& st) const { return divide(m_viewFromSurface * glm::dvec3(st, 1.0)); }
    dvec2 toSurface(const dvec2& uv) const { return divide(m_surfaceFromView * glm::dvec3(uv, 1.0)); }
    // Homogeneous weight of a surface point: > 0 when it lies in front of the eye.
    double weight(const dvec2& st) const { return (m_viewFromSurface * glm::dvec3(st, 1.0)).z; }

    // CoP_s: the point of the base plane closest to the eye; CoP_v: its image (the vanishing
    // point of vertical lines, through which every visibility line passes).
    dvec2 copSurface() const { return m_copSurface; }
    dvec2 copView() const { return m_copView; }
    const glm::dmat3& viewFromSurface() const { return m_viewFromSurface; }
    const glm::dmat3& surfaceFromView() const { return m_surfaceFromView; }

private:
    static dvec2 divide(const glm::dvec3& h) { return {h.x / h.z, h.y / h.z}; }

    glm::dmat3 m_viewFromSurface, m_surfaceFromView;
    dvec2 m_copSurface, m_copView;
};

}  // namespace relief::curves
