#pragma once
// The reference walk over the cells a ray crosses (DESIGN §3: Amanatides–Woo, both triangles of
// each cell), restricted to [ta, tb]. Over the whole clipped span with toExit it is the `exact`
// row's tracer; the safety marches and relaxed-cone's rising rays walk parts of rays with it.
// GLSL twin: cell_walk.glsl (same names).
#include <relief/surface/cell_cursor.h>
#include <relief/surface/cell_intersect.h>

#include <algorithm>
#include <cmath>

namespace relief {

inline void setHit(const Ray& ray, float t, Hit& hit) {
    hit.hit = true;
    hit.t = t;
    hit.position = ray.at(t);
}

// First hit on S in [ta, tb], counting one step and 4 fetches per cell; toExit: tb is the box
// exit, where leaving through the bottom face is a hit. True (and `hit` set) on a hit.
inline bool cellsHit(const Surface& s, const Ray& ray, float ta, float tb, bool toExit,
                     Hit& hit) {
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    const vec3 start = ray.at(ta);
    int ci = s.cellOfX(start.x), cj = s.cellOfY(start.y);
    const int stepX = d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0);
    const int stepY = d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0);
    const float invX = 1.0f / d.x, invY = 1.0f / d.y;
    const bool clamp = s.edge() == EdgeMode::Clamp;
    for (;;) {
        // Boundaries from the cell index each time: no drift from accumulated increments.
        const float tx =
            stepX == 0 ? kInfinity : (float(ci) + (stepX > 0 ? 1.5f : 0.5f) - o.x) * invX;
        const float ty =
            stepY == 0 ? kInfinity : (float(cj) + (stepY > 0 ? 1.5f : 0.5f) - o.y) * invY;
        const float tc = std::max(ta, std::min({tx, ty, tb}));
        ++hit.steps;
        hit.fetches += 4;
        const float t = firstHitInCell(s.cellPlanes(ci, cj), ray, ci, cj, ta, tc);
        if (t <= tc) {
            setHit(ray, t, hit);
            return true;
        }
        if (tc >= tb) {
            if (toExit && exitsThroughFloor(s, ray, tb)) {
                setHit(ray, tb, hit);
                return true;
            }
            return false;
        }
        if (tx <= ty) ci += stepX; else cj += stepY;
        if (clamp && (ci < -1 || ci > s.width() - 1 || cj < -1 || cj > s.height() - 1))
            return false;
        ta = tc;
    }
}

}  // namespace relief
