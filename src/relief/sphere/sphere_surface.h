#pragma once
// The displaced sphere of DESIGN §6: centre at the origin, base radius R, pole on +z; the point
// in unit direction n lies at radius R + D·h(n).
//
// h over the sphere: texel x = W·(longitude + π)/2π (longitude = atan2(n.y, n.x)), texel
// y = H·(π − colatitude)/π (row 0 at the south pole, so that texel x × texel y is the outward
// normal, as z is on the plane), and D·h is S of DESIGN §2 at (x, y): the same lower-diagonal
// triangles as on the plane, wrapping in x across the date line, and with y clamped to the
// sample-centre rows [0.5, H − 0.5] so that nothing wraps over a pole (the polar caps repeat the
// first and last rows). Note that a heightfield whose first or last row is not constant makes
// the displaced surface fan out at that pole: the pole is a segment from R + D·min to R + D·max.
#include <relief/core/heightfield.h>
#include <relief/surface/surface.h>

#include <glm/glm.hpp>

#include <memory>

namespace relief {

using glm::dmat3;
using glm::dvec2;
using glm::dvec3;

class SphereSurface {
public:
    SphereSurface(std::shared_ptr<const Heightfield> heightfield, double radius, double depth);

    double radius() const { return m_radius; }
    double depth() const { return m_grid->depth(); }
    double maxRadius() const { return m_radius + double(m_grid->maxZ()); }
    // The heightfield as a repeat-mode Surface: its texel space is where shading maps are read.
    const Surface& grid() const { return *m_grid; }

    // Texel coordinates (x, y) of a unit direction, y not yet clamped.
    dvec2 texelOf(const dvec3& n) const;
    double heightAt(const dvec3& n) const;  // D·h, in world units
    // Texel-space point of the surface in direction n: (x, y, D·h).
    vec3 texelPoint(const dvec3& n) const;
    // Outward normal of the displaced surface and its tangent frame (columns: texel x, texel y,
    // outward base normal), both in world coordinates.
    struct Frame {
        dvec3 normal;
        dmat3 tangentToWorld;
        dvec3 tangentNormal;  // `normal` in the tangent frame
    };
    Frame frameAt(const dvec3& n) const;

private:
    dvec2 gridPoint(const dvec3& n, bool* clampedY = nullptr) const;

    double m_radius;
    std::shared_ptr<const Surface> m_grid;
};

}  // namespace relief
