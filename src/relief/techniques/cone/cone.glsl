// cone — GLSL twin of relief::ConeTracer::trace (cone.h): the same cone steps, the same exact
// cell finish, the same step and fetch counts.
// requires: common/cone_maps.glsl

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const vec3 d = ray.direction;
    precise float horizontalSquared = d.x * d.x + d.y * d.y;
    const float horizontal = squareRoot(horizontalSquared);
    const int maxSteps = paramInt(kParamMaxSteps);
    float t = span.tEnter;
    while (hit.steps < maxSteps) {
        ++hit.steps;
        const vec3 p = at(ray, t);
        const vec2 cone = coneAt(p.x, p.y);
        ++hit.fetches;
        if (p.z >= cone.x && p.z > 0.0) {  // on the floor the cell test decides (cone.h)
            const float dt = coneStep(p.z, cone.x, cone.y, horizontal, d.z);
            if (dt >= kConeStall) {
                precise float tNext = t + dt;
                if (tNext >= span.tExit)  // leaves the box without meeting S inside it
                    return exitsThroughFloor(ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
                t = tNext;
                continue;
            }
        }
        // Exact: the cell the ray is in, up to where it leaves it.
        const CellSpan cell = cellAt(ray, t, span.tExit);
        hit.fetches += 4;
        const float th =
            firstHitInCell(cellPlanes(cell.ci, cell.cj), ray, cell.ci, cell.cj, t, cell.tb);
        if (th <= cell.tb) return hitAt(ray, th, hit);
        if (cell.tb >= span.tExit)
            return exitsThroughFloor(ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
        t = cell.tb;
    }
    return hitAt(ray, t, hit);  // capped: the last position, never past the first hit
}
