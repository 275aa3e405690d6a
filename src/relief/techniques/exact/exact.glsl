// exact — GLSL twin of relief::ExactTracer::trace (exact.h): the clipped span walked by cellsHit
// (surface/cell_walk.glsl, the same grid walk and per-cell test), the same step and fetch counts.
// requires: surface/cell_walk.glsl

Hit trace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (!empty(span)) cellsHit(ray, span.tEnter, span.tExit, true, hit);
    return hit;
}
