#pragma once
// Exact first hit of a ray segment with S inside one cell. S is the max of the cell's two planes,
// so the ray is on or below S iff it is on or below either plane; along the ray each
// "height above plane" is linear in t, which makes the test two sign checks and one division.
#include <relief/surface/surface.h>

#include <algorithm>

namespace relief {

// Smallest t in [ta, tb] where the ray is on or below `plane`, or kInfinity. The hit/miss
// decision is the float sign test at both ends (as the GLSL twin makes it). The root is solved in
// double: the height above the plane is a + b·t, and a subtracts the plane's height under the
// origin from the origin's, which cancels badly in float for far origins and grazing rays (a float
// secant put one contract ray 1.1e-4 texel past the true t at t ≈ 143).
inline float firstHitOnPlane(const CellPlane& plane, const vec3& origin, const vec3& direction,
                             float cellX, float cellY, float ta, float tb) {
    const float ou = origin.x - cellX, ov = origin.y - cellY;
    const float above0 = origin.z + ta * direction.z -
                         plane.at(ou + ta * direction.x, ov + ta * direction.y);
    if (above0 <= 0.0f) return ta;
    const float above1 = origin.z + tb * direction.z -
                         plane.at(ou + tb * direction.x, ov + tb * direction.y);
    if (above1 > 0.0f) return kInfinity;
    const double du = double(origin.x) - double(cellX), dv = double(origin.y) - double(cellY);
    const double a = double(origin.z) - (double(plane.z0) + double(plane.sx) * du + double(plane.sy) * dv);
    const double b = double(direction.z) - double(plane.sx) * double(direction.x) -
                     double(plane.sy) * double(direction.y);
    // The float signs say the root lies in (ta, tb]; where rounding makes the double line
    // disagree (b >= 0, or its root outside), the segment's end that the signs name is kept.
    if (!(b < 0.0)) return tb;
    return std::clamp(float(-a / b), ta, tb);
}

// Smallest t in [ta, tb] where the ray is on or below S in cell (ci, cj), or kInfinity.
inline float firstHitInCell(const CellPlanes& planes, const Ray& ray, int ci, int cj, float ta,
                            float tb) {
    const float cellX = float(ci) + 0.5f, cellY = float(cj) + 0.5f;
    const float t0 =
        firstHitOnPlane(planes.first, ray.origin, ray.direction, cellX, cellY, ta, tb);
    if (t0 == ta) return t0;
    const float t1 =
        firstHitOnPlane(planes.second, ray.origin, ray.direction, cellX, cellY, ta, tb);
    return std::min(t0, t1);
}

}  // namespace relief
