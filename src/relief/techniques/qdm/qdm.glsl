// qdm — GLSL twin of relief::QdmTracer::trace (qdm.h): the same quadric steps, the same exact
// cell finish over referenceSpan, the same step and fetch counts.
// requires: qdm/qdm_map.glsl

const float kQdmStall = 0.1;      // QdmLimits::stall
const float kQdmShorten = 1e-4;   // QdmLimits::shorten

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const vec3 d = ray.direction;
    precise float horizontalSquared = d.x * d.x + d.y * d.y;
    const float horizontal = squareRoot(horizontalSquared);
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
