// maxmip — GLSL twin of relief::MaxmipTracer::trace (maxmip.h): walkPyramid with the flat max
// bound (MaxBound) and the Ancestor policy.
// requires: common/pyramid_walk.glsl

float boundEnter(NodeBox b, WalkRay r, float t, float tOut) {
    return maxBoundEnter(b, r, t, tOut, paramInt(kParamBits) < 32);
}

Hit trace(Ray ray) {
    return walkPyramid(kAscentAncestor, ray, WalkLimits(paramInt(kParamMaxSteps), false));
}
