// maxmip — maximum mipmaps (Tevs, Ihrke & Seidel 2008). Port of relief::MaxmipTracer::trace
// (src/relief/techniques/maxmip/maxmip.h): the max-pyramid walk going up to the common ancestor
// after each step. Maps: `heights` and `pyramid` (pyramid_walk.glsl). Contract: exact with
// p.maxSteps = 0 (no cap); N > 0 is approximate. The box surfaces (box-surface = 1, 2) are not
// offered here. Shadows: the same walk toward the light.
// requires: pyramid_walk.glsl

ReliefHit reliefMaxmip(sampler2D heights, sampler2D pyramid, vec2 uv, vec3 viewDirTangent,
                       ReliefParams p) {
    return reliefPyramidView(heights, pyramid, pyramid, kReliefBoundMax, uv, viewDirTangent,
                             kAscentAncestor, p);
}

float reliefMaxmipShadow(sampler2D heights, sampler2D pyramid, ReliefHit hit,
                         vec3 lightDirTangent, ReliefParams p) {
    return reliefPyramidShadow(heights, pyramid, pyramid, kReliefBoundMax, hit, lightDirTangent,
                               kAscentAncestor, p);
}
