// quadtree — GLSL twin of relief::QuadtreeTracer::trace (quadtree.h): walkPyramid with the flat
// max bound (MaxBound) and the Ascent policy from the `ascend` parameter. box-surface = 1 (cell
// boxes) as on the CPU; 2 (texel boxes) is CPU only (the GL backend refuses it: cpuOnly).
// requires: common/pyramid_walk.glsl

float boundEnter(NodeBox b, WalkRay r, float t, float tOut) {
    return maxBoundEnter(b, r, t, tOut, paramInt(kParamBits) < 32);
}

Hit trace(Ray ray) {
    const WalkLimits limits = WalkLimits(paramInt(kParamMaxSteps), paramInt(kParamBoxSurface) != 0);
    const int ascent = paramInt(kParamAscend) == 0 ? kAscentNone : kAscentParent;
    return walkPyramid(ascent, ray, limits);
}
