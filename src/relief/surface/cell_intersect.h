#pragma once
// Exact first hit of a ray segment with S inside one cell. S is the max of the cell's two planes,
// so the ray is on or below S iff it is on or below either plane; along the ray each
// "height above plane" is linear in t, which makes the test two sign checks and one division.
#include <relief/surface/surface.h>

#include <algorithm>

namespace relief {

// Smallest t in [ta, tb] where the ray is on or below `plane`, or kInfinity. The height above
// the plane is A + B·t; A subtracts the plane's height under the origin from the origin's, which
// cancels badly in float for far origins and grazing rays (t error ≈ ulp(z) / |B|, 1e-4 texel at
// t ≈ 140), so A, B and the root are computed in double and only the root is rounded to float.
inline float firstHitOnPlane(const CellPlane& plane, const vec3& origin, const vec3& direction,
                             float cellX, float cellY, float ta, float tb) {
    const double ou = double(origin.x) - double(cellX), ov = double(origin.y) - double(cellY);
    const double a = double(origin.z) - (double(plane.z0) + double(plane.sx) * ou + double(plane.sy) * ov);
    const double b = double(direction.z) - double(plane.sx) * double(direction.x) -
                     double(plane.sy) * double(direction.y);
    if (a + b * double(ta) <= 0.0) return ta;
    if (a + b * double(tb) > 0.0) return kInfinity;
    // above(ta) > 0 >= above(tb): b < 0 and the root lies in (ta, tb].
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
