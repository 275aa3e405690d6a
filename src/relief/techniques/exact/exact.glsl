// exact — GLSL twin of relief::ExactTracer::trace (exact.h): the same grid walk, the same
// per-cell test (common_cell_intersect.glsl), the same step and fetch counts.
// Departure: the loop has a cap that valid rays never reach (a NaN ray must not hang the GPU).

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    const vec3 entry = at(ray, span.tEnter);
    int ci = cellOfX(entry.x), cj = cellOfY(entry.y);
    const int stepX = d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0);
    const int stepY = d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0);
    const float invX = divide(1.0, d.x), invY = divide(1.0, d.y);
    const bool clampEdges = edge() == kEdgeClamp;  // `clamp` in C++; a built-in name in GLSL
    const int cellCap = 8 + 2 * int(kRepeatTravelFactor + 1.0) * (width() + height());
    float ta = span.tEnter;
    for (int guard = 0; guard < cellCap; ++guard) {
        // Boundaries from the cell index each time: no drift from accumulated increments.
        precise float tx =
            stepX == 0 ? kInfinity : (float(ci) + (stepX > 0 ? 1.5 : 0.5) - o.x) * invX;
        precise float ty =
            stepY == 0 ? kInfinity : (float(cj) + (stepY > 0 ? 1.5 : 0.5) - o.y) * invY;
        const float tb = max(ta, min(min(tx, ty), span.tExit));
        ++hit.steps;
        hit.fetches += 4;
        const float t = firstHitInCell(cellPlanes(ci, cj), ray, ci, cj, ta, tb);
        if (t <= tb) {
            hit.hit = true;
            hit.t = t;
            hit.position = at(ray, t);
            return hit;
        }
        if (tb >= span.tExit) {
            // Leaving through the bottom face means reaching z = 0 ≤ S: S is there. Where samples
            // are 0 the floor lies in that face and rounding can leave the cell test a hair
            // above it at tExit, so the test alone misses such hits.
            precise float zExit = o.z + span.tExit * d.z;
            precise float zRounding = 4.0 * kFloatEpsilon * (abs(o.z) + depth());
            if (d.z < 0.0 && zExit <= zRounding) {
                hit.hit = true;
                hit.t = span.tExit;
                hit.position = at(ray, span.tExit);
            }
            return hit;
        }
        if (tx <= ty) ci += stepX; else cj += stepY;
        if (clampEdges && (ci < -1 || ci > width() - 1 || cj < -1 || cj > height() - 1)) return hit;
        ta = tb;
    }
    return hit;
}
