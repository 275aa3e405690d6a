// The reference walk over [ta, tb] — GLSL twin of cellsHit and setHit in
// src/relief/surface/cell_walk.h; over the whole clipped span with toExit it is the `exact` row's
// tracer (exact.glsl), counts included. Not part of every program: a shader names it on a
// `// requires: surface/cell_walk.glsl` line.
// Departure: the loop has a cap that valid rays never reach (a NaN ray must not hang the GPU).

void setHit(Ray ray, float t, inout Hit hit) {
    hit.hit = true;
    hit.t = t;
    hit.position = at(ray, t);
}

// First hit on S in [ta, tb]; toExit: tb is the box exit, where leaving through the bottom face
// is a hit.
bool cellsHit(Ray ray, float ta, float tb, bool toExit, inout Hit hit) {
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    const vec3 start = at(ray, ta);
    int ci = cellOfX(start.x), cj = cellOfY(start.y);
    const int stepX = d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0);
    const int stepY = d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0);
    const float invX = divide(1.0, d.x), invY = divide(1.0, d.y);
    const bool clampEdges = edge() == kEdgeClamp;
    const int cellCap = 8 + 2 * int(kRepeatTravelFactor + 1.0) * (width() + height());
    for (int guard = 0; guard < cellCap; ++guard) {
        precise float tx =
            stepX == 0 ? kInfinity : (float(ci) + (stepX > 0 ? 1.5 : 0.5) - o.x) * invX;
        precise float ty =
            stepY == 0 ? kInfinity : (float(cj) + (stepY > 0 ? 1.5 : 0.5) - o.y) * invY;
        const float tc = max(ta, min(min(tx, ty), tb));
        ++hit.steps;
        hit.fetches += 4;
        const float t = firstHitInCell(cellPlanes(ci, cj), ray, ci, cj, ta, tc);
        if (t <= tc) {
            setHit(ray, t, hit);
            return true;
        }
        if (tc >= tb) {
            precise float zEnd = o.z + tb * d.z;
            precise float rounding = 4.0 * kFloatEpsilon * (abs(o.z) + depth());
            if (toExit && d.z < 0.0 && zEnd <= rounding) {
                setHit(ray, tb, hit);
                return true;
            }
            return false;
        }
        if (tx <= ty) ci += stepX; else cj += stepY;
        if (clampEdges && (ci < -1 || ci > width() - 1 || cj < -1 || cj > height() - 1))
            return false;
        ta = tc;
    }
    return false;
}

