// relaxed-cone — relaxed cone stepping then binary refinement (Policarpo & Oliveira 2007, GPU
// Gems 3 ch. 18). Port of relief::RelaxedConeTracer::trace and ::refine
// (src/relief/techniques/relaxed_cone/relaxed_cone.h): cone steps while they advance, then
// p.binarySteps bisections on exact S between the last two positions.
// Maps: `heights` (R32F, h in [0, 1]) and `cones`, the bake's "cones" array as RG32F (the
// encoding of cone.glsl; the decode is common.glsl's reliefConeAt), both nearest.
// Contract: approximate (relaxed cones may step past a hit; refinement finds one in between).
// Departure: view rays only descend here; the C++ tracer walks rising rays cell by cell.
// Shadows: reliefShadowMarch (p.maxSteps samples toward the light).
// requires: common.glsl

bool reliefRelaxedBelow(sampler2D heights, ReliefRay ray, float t, ReliefParams p) {
    vec3 q = ray.origin + t * ray.direction;
    return q.z <= reliefHeightAt(heights, q.x, q.y, p);
}

ReliefHit reliefRelaxedCone(sampler2D heights, sampler2D cones, vec2 uv, vec3 viewDirTangent,
                            ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    vec3 d = ray.direction;
    if (!(d.z < 0.0)) return reliefNoHit(0);
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    float horizontal = sqrt(d.x * d.x + d.y * d.y);
    float t = span.x, tPrev = t;
    if (reliefRelaxedBelow(heights, ray, t, p)) return reliefHitAt(ray, t, 0, p);  // side wall
    int steps = 0;
    for (int k = 0; k < p.maxSteps; ++k) {
        ++steps;
        vec3 q = ray.origin + t * d;
        vec2 cone = reliefConeAt(cones, q.x, q.y, p);
        float dt = q.z > cone.x ? reliefConeStep(q.z, cone.x, cone.y, horizontal, d.z) : 0.0;
        if (!(dt > 0.0)) break;
        tPrev = t;
        t = min(t + dt, span.y);
        if (t >= span.y) break;
    }
    // Refinement between the last position above S (tPrev) and the last one reached (t).
    float lo = tPrev, hi = t;
    if (!reliefRelaxedBelow(heights, ray, hi, p)) {
        if (hi < span.y) return reliefHitAt(ray, hi, steps, p);  // not converged: the last position
        return reliefHitIf(reliefExitsThroughFloor(ray, span.y, p), ray, span.y, steps, p);
    }
    for (int k = 0; k < p.binarySteps; ++k) {
        ++steps;
        float mid = 0.5 * (lo + hi);
        if (reliefRelaxedBelow(heights, ray, mid, p)) hi = mid; else lo = mid;
    }
    return reliefHitAt(ray, lo, steps, p);  // the last position above S
}

float reliefRelaxedConeShadow(sampler2D heights, sampler2D cones, ReliefHit hit,
                              vec3 lightDirTangent, ReliefParams p) {
    return reliefShadowMarch(heights, hit, lightDirTangent, p);
}
