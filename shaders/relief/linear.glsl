// linear — relief mapping (POM): N linear steps then M bisection steps on bilinear heights.
// Port of relief::LinearTracer::trace (src/relief/techniques/linear/linear.h): the N steps
// divide the ray's interval inside the box, a ray still above S after them is a miss.
// Parameters: p.maxSteps = N (engines' "max layers"), p.binarySteps = M.
// Maps: `heights` only (R32F, h in [0, 1]; fetched with texelFetch and interpolated here, with
// full-precision weights, so no filtering is needed).
// Contract: approximate (a step can jump over thin features). Shadows: reliefLinearShadow.
// requires: common.glsl

bool reliefLinearBelow(sampler2D heights, ReliefRay ray, float t, ReliefParams p) {
    vec3 q = ray.origin + t * ray.direction;
    return q.z <= reliefBilinearZ(heights, q.x, q.y, p);
}

ReliefHit reliefLinear(sampler2D heights, vec2 uv, vec3 viewDirTangent, ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    int n = max(p.maxSteps, 1);
    float dt = (span.y - span.x) / float(n);
    float tAbove = span.x, tBelow = kReliefInfinity;
    int steps = 0;
    if (reliefLinearBelow(heights, ray, span.x, p)) {
        tBelow = span.x;
    } else {
        for (int k = 1; k <= n; ++k) {
            ++steps;
            float t = k == n ? span.y : span.x + float(k) * dt;
            if (reliefLinearBelow(heights, ray, t, p)) {
                tBelow = t;
                break;
            }
            tAbove = t;
        }
        if (tBelow == kReliefInfinity) return reliefNoHit(steps);
        for (int k = 0; k < p.binarySteps; ++k) {
            ++steps;
            float mid = 0.5 * (tAbove + tBelow);
            if (reliefLinearBelow(heights, ray, mid, p)) tBelow = mid; else tAbove = mid;
        }
    }
    return reliefHitAt(ray, tBelow == span.x ? tBelow : 0.5 * (tAbove + tBelow), steps, p);
}

float reliefLinearShadow(sampler2D heights, ReliefHit hit, vec3 lightDirTangent, ReliefParams p) {
    return reliefShadowMarch(heights, hit, lightDirTangent, p);
}
