#pragma once
// The cell cursor of the map-stepping tracers' exact parts (cone, relaxed-cone, qdm): the cell a
// ray is in at t and where it leaves it, whether leaving the box is a floor hit, and a Hit at t.
// GLSL twin: cell_cursor.glsl (same names).
#include <relief/surface/surface.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace relief {

// The cell the ray is in at t, moving along its direction, and where it leaves it (≤ tEnd).
struct CellSpan {
    int ci, cj;
    float tb;
};
inline CellSpan cellAt(const Surface& s, const Ray& ray, float t, float tEnd) {
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    const vec3 p = ray.at(t);
    auto exitAlong = [](int cell, float origin, float dir) {
        if (dir == 0.0f) return kInfinity;
        return (float(cell) + (dir > 0.0f ? 1.5f : 0.5f) - origin) / dir;
    };
    int ci = int(std::floor(p.x - 0.5f)), cj = int(std::floor(p.y - 0.5f));
    float tx = exitAlong(ci, o.x, d.x), ty = exitAlong(cj, o.y, d.y);
    if (tx <= t) tx = exitAlong(ci += d.x > 0.0f ? 1 : -1, o.x, d.x);  // on the edge: move on
    if (ty <= t) ty = exitAlong(cj += d.y > 0.0f ? 1 : -1, o.y, d.y);
    if (s.edge() == EdgeMode::Clamp) {
        ci = std::clamp(ci, -1, s.width() - 1);
        cj = std::clamp(cj, -1, s.height() - 1);
    }
    return {ci, cj, std::max(t, std::min({tx, ty, tEnd}))};
}

// Leaving the box through its bottom face reaches z = 0 ≤ S: S is there. Where samples are 0 the
// floor lies in that face and rounding can leave a cell test a hair above it at the exit, so the
// test alone misses such hits (every walk's rule at the box exit: cellsHit, the marches).
inline bool exitsThroughFloor(const Surface& s, const Ray& ray, float tExit) {
    const float zExit = ray.origin.z + tExit * ray.direction.z;
    const float zRounding =
        4.0f * std::numeric_limits<float>::epsilon() * (std::abs(ray.origin.z) + s.depth());
    return ray.direction.z < 0.0f && zExit <= zRounding;
}

inline Hit hitAt(const Ray& ray, float t, Hit hit) {
    hit.hit = true;
    hit.t = t;
    hit.position = ray.at(t);
    return hit;
}

}  // namespace relief
