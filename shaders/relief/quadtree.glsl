// quadtree — quadtree relief mapping (Schroders & van Gulik 2006). Port of
// relief::QuadtreeTracer::trace (src/relief/techniques/quadtree/quadtree.h): the max-pyramid
// walk jumping to the neighbour node; p.ascend = 1 (relief's default) goes up one level on
// entering a new parent, 0 is the paper's walk. Maps: `heights` and `pyramid`
// (pyramid_walk.glsl). Contract: exact with p.maxSteps = 0; N > 0 (the paper's fixed loop) is
// approximate. The box surfaces (box-surface = 1 cell boxes, 2 the paper's texel boxes) are not
// offered here.
// Shadows: the same walk toward the light.
// requires: pyramid_walk.glsl

int reliefQuadtreeAscent(ReliefParams p) { return p.ascend == 0 ? kAscentNone : kAscentParent; }

ReliefHit reliefQuadtree(sampler2D heights, sampler2D pyramid, vec2 uv, vec3 viewDirTangent,
                         ReliefParams p) {
    return reliefPyramidView(heights, pyramid, pyramid, kReliefBoundMax, uv, viewDirTangent,
                             reliefQuadtreeAscent(p), p);
}

float reliefQuadtreeShadow(sampler2D heights, sampler2D pyramid, ReliefHit hit,
                           vec3 lightDirTangent, ReliefParams p) {
    return reliefPyramidShadow(heights, pyramid, pyramid, kReliefBoundMax, hit, lightDirTangent,
                               reliefQuadtreeAscent(p), p);
}
