// qdm — GLSL twin of relief::QdmTracer::trace (qdm.h): the same quadric steps, the same exact
// cell finish over referenceSpan, the same step and fetch counts; variant 1 (`paper`) is
// QdmPaperTracer::trace and paperStep (qdm_paper.h), rising rays on the reference walk.
// requires: qdm/qdm_map.glsl
// requires: surface/cell_walk.glsl

const float kQdmStall = 0.1;      // QdmLimits::stall
const float kQdmShorten = 1e-4;   // QdmLimits::shorten

// paperStep: Algorithm 1's line to (a, b) while alpha ≤ 1, else Algorithm 2's root.
float paperStep(QdmTexel q, float h0, float horizontal, float dz) {
    if (q.a > 0.0) {
        const float slope = divide(q.b, q.a);
        precise float closing = slope * horizontal - dz;
        const float t = divide(h0, closing);
        precise float travel = t * horizontal;
        if (divide(travel, q.a) <= 1.0) return t;
    }
    precise float A = horizontal * horizontal;
    precise float halfB = 0.5 * (dz - 2.0 * q.c * horizontal);
    precise float C = h0 - q.b - q.a * q.a + 2.0 * q.a * q.c;
    precise float disc = halfB * halfB - A * C;
    if (disc < 0.0) return kInfinity;
    precise float denominator = -halfB + squareRoot(disc);
    const float x = divide(C, denominator);
    return abs(x) < kInfinity ? x : kInfinity;  // std::isfinite
}

// QdmPaperTracer::trace after the clip.
Hit tracePaper(Ray ray, RayInterval span, float horizontal) {
    Hit hit = noHit();
    const vec3 d = ray.direction;
    if (d.z >= 0.0) {  // ExactTracer::trace
        cellsHit(ray, span.tEnter, span.tExit, true, hit);
        return hit;
    }
    const int maxSteps = paramInt(kParamMaxSteps);
    float t = span.tEnter;
    float dt = kInfinity;
    while (hit.steps < maxSteps && dt > kQdmPaperEpsilon) {
        const vec3 p = at(ray, t);
        const QdmTexel q = qdmAt(p.x, p.y);
        ++hit.fetches;
        if (!(p.z > q.h)) break;  // p is not above the heightfield
        precise float h0 = p.z - q.h;
        dt = paperStep(q, h0, horizontal, d.z);
        ++hit.steps;
        precise float tNext = t + dt;
        t = tNext < span.tEnter ? span.tEnter : tNext;  // std::max(t + dt, tEnter)
        if (!(t < span.tExit)) break;
    }
    if (!(t < span.tExit))
        return exitsThroughFloor(ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
    return hitAt(ray, t, hit);
}

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const vec3 d = ray.direction;
    precise float horizontalSquared = d.x * d.x + d.y * d.y;
    const float horizontal = squareRoot(horizontalSquared);
    if (paramInt(kParamVariant) == 1) return tracePaper(ray, span, horizontal);
    const int maxSteps = paramInt(kParamMaxSteps);
    precise float keep = 1.0 - kQdmShorten;
    float t = span.tEnter;
    while (hit.steps < maxSteps) {
        ++hit.steps;
        const vec3 p = at(ray, t);
        const QdmTexel q = qdmAt(p.x, p.y);
        ++hit.fetches;
        if (p.z > q.h) {  // on the apex height the ray may touch S: the cell test decides
            precise float dt = keep * quadricStep(q, p.z, horizontal, d.z, qdmReach(q));
            if (dt >= kQdmStall) {
                precise float tNext = t + dt;
                if (tNext >= span.tExit)  // leaves the box without meeting S inside it
                    return exitsThroughFloor(ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
                t = tNext;
                continue;
            }
        }
        // Exact: the cell the ray is in, from where it entered it to where it leaves it.
        const CellSpan cell = cellAt(ray, t, span.tExit);
        const vec2 cellSpan = referenceSpan(ray, cell.ci, cell.cj, span);
        hit.fetches += 4;
        const float th = firstHitInCell(cellPlanes(cell.ci, cell.cj), ray, cell.ci, cell.cj,
                                        cellSpan.x, cellSpan.y);
        if (th <= cellSpan.y) return hitAt(ray, th, hit);
        if (cellSpan.y >= span.tExit)
            return exitsThroughFloor(ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
        t = cellSpan.y > t ? cellSpan.y : cell.tb;
    }
    return hitAt(ray, t, hit);  // capped: the last position, never past the first hit
}
