// linear — GLSL twin of relief::LinearTracer::trace (linear.h): N linear steps over the ray's
// interval in the box, then M bisection steps, on bilinear height fetches (bilinearZ).
// Parameters: max-steps = N (kParamMaxSteps), binary-steps = M (kParamBinarySteps).

int linearSteps() { return paramInt(kParamMaxSteps); }
int binarySteps() { return paramInt(kParamBinarySteps); }

bool below(Ray ray, float t, inout Hit hit) {
    const vec3 p = at(ray, t);
    ++hit.fetches;
    return p.z <= bilinearZ(p.x, p.y);
}

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const int n = linearSteps();
    precise float dt = divide(span.tExit - span.tEnter, float(n));
    float tAbove = span.tEnter, tBelow = kInfinity;
    if (below(ray, span.tEnter, hit)) {
        tBelow = span.tEnter;
    } else {
        for (int k = 1; k <= n; ++k) {
            ++hit.steps;
            precise float t = k == n ? span.tExit : span.tEnter + float(k) * dt;
            if (below(ray, t, hit)) {
                tBelow = t;
                break;
            }
            tAbove = t;
        }
        if (tBelow == kInfinity) return hit;
        for (int k = 0; k < binarySteps(); ++k) {
            ++hit.steps;
            precise float mid = 0.5 * (tAbove + tBelow);
            if (below(ray, mid, hit)) tBelow = mid; else tAbove = mid;
        }
    }
    hit.hit = true;
    hit.t = tBelow == span.tEnter ? tBelow : 0.5 * (tAbove + tBelow);
    hit.position = at(ray, hit.t);
    return hit;
}
