// parallax — GLSL twin of relief::ParallaxTracer::trace (parallax.h): one bilinear fetch below
// the box entry point, the offset-limited shift t = tEnter + depth below the entry.

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const vec3 entry = at(ray, span.tEnter);
    hit.steps = 1;
    hit.fetches = 1;
    const float depthBelowEntry = max(0.0, entry.z - bilinearZ(entry.x, entry.y));
    precise float t = span.tEnter + depthBelowEntry;
    if (t > span.tExit) return hit;
    hit.hit = true;
    hit.t = t;
    hit.position = at(ray, t);
    return hit;
}
