// safety-sd — GLSL twin of relief::SafetySdTracer::trace (safety_sd.h):
// SafetyTracer<DistanceShape>::trace (safety_common/safety_march.glsl) with DistanceShape::step
// over the map "sd" (one channel per ray class, or one when isotropic).
// requires: safety_common/safety_march.glsl

// DistanceShape::step: the stored distance, whatever the ray's height.
int shapeStep(int cls, int i, int j, float z, float slope) {
    return int(mapTexel(kMapSd, i, j, kMapChannels[kMapSd] == 1 ? 0 : cls));
}

Hit trace(Ray ray) { return safetyTrace(ray); }
