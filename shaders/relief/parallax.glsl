// parallax — parallax mapping with offset limiting (Kaneko et al. 2001, Welsh 2004). Port of
// relief::ParallaxTracer::trace (src/relief/techniques/parallax/parallax.h): one bilinear
// height fetch below where the ray enters the box; the point δ further along the ray, δ the
// depth of S below the entry, is the hit (a shift of δ·|d.xy| in texels).
// Maps: `heights` only (R32F, h in [0, 1]). Contract: approximate, 1 step.
// Shadows: reliefShadowMarch (p.maxSteps samples toward the light).
// requires: common.glsl

ReliefHit reliefParallax(sampler2D heights, vec2 uv, vec3 viewDirTangent, ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    vec3 entry = ray.origin + span.x * ray.direction;
    float depthBelowEntry = max(0.0, entry.z - reliefBilinearZ(heights, entry.x, entry.y, p));
    float t = span.x + depthBelowEntry;
    if (t > span.y) return reliefNoHit(1);
    return reliefHitAt(ray, t, 1, p);
}

float reliefParallaxShadow(sampler2D heights, ReliefHit hit, vec3 lightDirTangent,
                           ReliefParams p) {
    return reliefShadowMarch(heights, hit, lightDirTangent, p);
}
