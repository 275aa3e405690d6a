// maxmip — GLSL twin of relief::MaxmipTracer::trace (maxmip.h): walkPyramid with the flat max
// bound (MaxBound) and the Ancestor policy; box-surface = 1 (cell boxes) as on the CPU, 2 (texel
// boxes) is CPU only (the GL backend refuses it: VariantSpec::cpuOnly).
// requires: common/pyramid_walk.glsl

float boundEnter(NodeBox b, WalkRay r, float t, float tOut) {
    return maxBoundEnter(b, r, t, tOut, paramInt(kParamBits) < 32);
}

Hit trace(Ray ray) {
    const WalkLimits limits = WalkLimits(paramInt(kParamMaxSteps), paramInt(kParamBoxSurface) != 0);
    return walkPyramid(kAscentAncestor, ray, limits);
}
