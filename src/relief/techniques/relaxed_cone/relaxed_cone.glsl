// relaxed-cone — GLSL twin of relief::RelaxedConeTracer::trace and ::refine (relaxed_cone.h):
// relaxed cone steps, then binary refinement on exact S; rising rays take the reference walk
// (ExactTracer::trace there: cellsHit over the clipped span).
// requires: common/cone_maps.glsl
// requires: surface/cell_walk.glsl

Hit refine(Ray ray, float lo, float hi, float tExit, Hit hit) {
    hit.fetches += 4;
    vec3 q = at(ray, hi);
    if (!(q.z <= heightAt(q.x, q.y))) {
        if (hi < tExit) return hitAt(ray, hi, hit);  // not converged: the last position
        return exitsThroughFloor(ray, tExit) ? hitAt(ray, tExit, hit) : hit;
    }
    const int binarySteps = paramInt(kParamBinarySteps);
    for (int k = 0; k < binarySteps; ++k) {
        ++hit.steps;
        precise float mid = 0.5 * (lo + hi);
        hit.fetches += 4;
        q = at(ray, mid);
        if (q.z <= heightAt(q.x, q.y)) hi = mid; else lo = mid;
    }
    return hitAt(ray, lo, hit);  // the last position above S
}

Hit trace(Ray ray) {
    const vec3 d = ray.direction;
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    if (d.z >= 0.0) {  // ExactTracer::trace
        cellsHit(ray, span.tEnter, span.tExit, true, hit);
        return hit;
    }
    precise float horizontalSquared = d.x * d.x + d.y * d.y;
    const float horizontal = squareRoot(horizontalSquared);
    float t = span.tEnter, tPrev = t;
    const vec3 entry = at(ray, t);
    hit.fetches += 4;
    if (entry.z <= heightAt(entry.x, entry.y)) return hitAt(ray, t, hit);  // side wall
    const int maxSteps = paramInt(kParamMaxSteps);
    while (hit.steps < maxSteps) {
        ++hit.steps;
        const vec3 p = at(ray, t);
        const vec2 cone = coneAt(p.x, p.y);
        ++hit.fetches;
        const float dt = p.z > cone.x ? coneStep(p.z, cone.x, cone.y, horizontal, d.z) : 0.0;
        if (!(dt > 0.0)) break;
        tPrev = t;
        precise float tNext = t + dt;
        t = min(tNext, span.tExit);
        if (t >= span.tExit) break;
    }
    return refine(ray, tPrev, t, span.tExit, hit);
}
