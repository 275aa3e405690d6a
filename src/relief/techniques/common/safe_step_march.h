#pragma once
// The loop the conservative step maps share (cone: safe cones; qdm: cone + revolved parabola):
// from where the ray enters the box, step by the map's safe distance while that is at least
// `stall`; otherwise test the cell the ray is in exactly and go on from where it leaves the cell.
// Never past the first hit; at the cap, the last position (still before the first hit).
// GLSL: cone.glsl and qdm.glsl keep this loop inline (same names, same order of operations).
#include <relief/surface/cell_cursor.h>
#include <relief/surface/cell_intersect.h>

#include <cmath>

namespace relief {

struct SafeStepLimits {
    int maxSteps;
    float stall;  // a step shorter than this goes to the exact cell test instead
};

// The part of a cell to test, and where to go on: {from, to, next}.
struct CellRangeAlong {
    float from, to, next;
};

// `safeStep(p, horizontal, hit)` fetches the map at p (counting its fetches in hit) and returns
// the safe distance along the ray, or -infinity where only the cell test may decide.
// `cellRange(cell, t, span)` gives {from, to, next}: the part of the cell to test exactly and
// where the march goes on when it holds no hit.
template <class SafeStep, class CellRange>
inline Hit safeStepMarch(const Surface& s, const Ray& ray, SafeStepLimits limits,
                         SafeStep&& safeStep, CellRange&& cellRange) {
    Hit hit;
    const RayInterval span = s.clip(ray);
    if (span.empty()) return hit;
    const vec3& d = ray.direction;
    const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
    float t = span.tEnter;
    while (hit.steps < limits.maxSteps) {
        ++hit.steps;
        const vec3 p = ray.at(t);
        const float dt = safeStep(p, horizontal, hit);
        if (dt >= limits.stall) {
            if (t + dt >= span.tExit)  // leaves the box without meeting S inside it
                return exitsThroughFloor(s, ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
            t += dt;
            continue;
        }
        // Exact: the cell the ray is in.
        const CellSpan cell = cellAt(s, ray, t, span.tExit);
        const auto [from, to, next] = cellRange(cell, t, span);
        hit.fetches += 4;
        const float th = firstHitInCell(s.cellPlanes(cell.ci, cell.cj), ray, cell.ci, cell.cj, from, to);
        if (th <= to) return hitAt(ray, th, hit);
        if (to >= span.tExit)
            return exitsThroughFloor(s, ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
        t = next;
    }
    return hitAt(ray, t, hit);  // capped: the last position, never past the first hit
}


}  // namespace relief
