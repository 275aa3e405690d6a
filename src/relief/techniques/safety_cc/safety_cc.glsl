// safety-cc — GLSL twin of relief::SafetyCcTracer::trace (safety_cc.h):
// SafetyTracer<ConeShape>::trace (safety_common/safety_march.glsl) with ConeShape::step over the
// maps "cc" (isotropic) or "ccx+", "ccx-", "ccy+", "ccy-" (channels r, z_c, s_c).
// requires: safety_common/safety_march.glsl

int coneArray(int cls) {
#ifdef RELIEF_MAP_CC
    return kMapCc;
#else
    return cls == 0 ? kMapCcxPlus : cls == 1 ? kMapCcxMinus : cls == 2 ? kMapCcyPlus : kMapCcyMinus;
#endif
}

// ConeShape::step: i = max(r, ⌊max(p_z − z0, 0)/(s_c − s_d)⌋).
int shapeStep(int cls, int i, int j, float z, float slope) {
    const int map = coneArray(cls);
    const float r = mapTexel(map, i, j, 0), zc = mapTexel(map, i, j, 1);
    const float coneSlope = mapTexel(map, i, j, 2);
    precise float z0 = zc - r * coneSlope;  // as coneMapFromArrays
    precise float above = z - z0;
    if (above <= 0.0) return int(r);
    precise float closing = coneSlope - slope;
    if (closing <= 0.0) return kFarStep;  // the ray rises at least as fast as the cone
    return max(int(r), int(min(divide(above, closing), float(kFarStep))));
}

Hit trace(Ray ray) { return safetyTrace(ray); }
