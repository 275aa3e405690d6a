// quadtree-oriented — the oriented quadtree (Schroders & van Gulik 2006 §5). Port of
// relief::QuadtreeOrientedTracer::trace (src/relief/techniques/quadtree_oriented/
// quadtree_oriented.h): the quadtree walk (Parent policy) whose nodes above level 0 carry a plane
// lying on S: the flat max as a pre-test, then where the ray goes below the plane.
// Maps: `heights`, `pyramid` (pyramid_walk.glsl: the flat max pyramid "level0"..) and
// `oriented`, the arrays "oriented1".."oriented<top>" as the mip levels 0.. of one RGBA32F
// texture ((c00, c10, c01, zmax) per node: the plane's heights at the node's corners and its
// maximum), nearest. Contract: exact (p.maxSteps = 0). Shadows: the same walk toward the light.
// requires: pyramid_walk.glsl

ReliefHit reliefQuadtreeOriented(sampler2D heights, sampler2D pyramid, sampler2D oriented,
                                 vec2 uv, vec3 viewDirTangent, ReliefParams p) {
    return reliefPyramidView(heights, pyramid, oriented, kReliefBoundOriented, uv, viewDirTangent,
                             kAscentParent, p);
}

float reliefQuadtreeOrientedShadow(sampler2D heights, sampler2D pyramid, sampler2D oriented,
                                   ReliefHit hit, vec3 lightDirTangent, ReliefParams p) {
    return reliefPyramidShadow(heights, pyramid, oriented, kReliefBoundOriented, hit,
                               lightDirTangent, kAscentParent, p);
}
