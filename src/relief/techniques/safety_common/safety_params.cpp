#include <relief/techniques/safety_common/safety_params.h>

namespace relief::safety {

BuildOptions buildOptionsFrom(const ParamValues& params) {
    BuildOptions o;
    o.phiMaxDeg = params.get("phi-max");
    o.isotropic = params.getInt("isotropic") != 0;
    o.exterior = params.getInt("exterior") != 0;
    o.exteriorSlope = params.has("exterior-slope") && params.getInt("exterior-slope") != 0;
    return o;
}

MarchOptions marchOptionsFrom(const ParamValues& params, const BuildOptions& build) {
    MarchOptions m;
    m.maxSteps = params.getInt("max-steps");
    m.phiMaxDeg = build.phiMaxDeg;
    m.exterior = build.exterior;
    m.viewDependent = params.getInt("view-dependent") != 0;
    m.positiveDistance = params.getInt("positive-distance") != 0;
    m.phiOutside = params.getInt("phi-outside") != 0;
    return m;
}

std::string phiMaxViewWarning(const ParamValues& params, std::span<const Ray> rays) {
    const double phiMax = params.get("phi-max");
    const double tanPhi = tanPhiMax(phiMax);
    size_t outside = 0;
    for (const Ray& r : rays) outside += !rayWithinPhiMax(r.direction, tanPhi);
    if (outside == 0) return {};
    if (params.getInt("phi-outside") != 0)
        return fmt::format("{:.1f}% of the primary rays are outside the maps' viewing-angle "
                           "restriction (phi-max {}): phi-outside=1 marches them on the maps anyway "
                           "(approximate: they can step past a hit)",
                           100.0 * double(outside) / double(rays.size()), phiMax);
    return fmt::format("{:.1f}% of the primary rays are outside the maps' viewing-angle restriction "
                       "(phi-max {}): they take the exact walk, which is slower (results stay exact)",
                       100.0 * double(outside) / double(rays.size()), phiMax);
}

std::string viewWarning(const ParamValues& params, std::span<const Ray> rays) {
    std::string warning = phiMaxViewWarning(params, rays);
    if (params.getInt("exterior") == 0 || rays.empty()) return warning;
    const vec3& o = rays.front().origin;
    if (!warning.empty()) warning += "; ";
    return warning + fmt::format("the maps serve exterior viewpoints only: if the camera "
                                 "({:.1f}, {:.1f}, {:.1f}) is inside the relief's box below its "
                                 "highest sample, its rays take the exact walk (results stay exact)",
                                 o.x, o.y, o.z);
}

Result<BuildOptions> bakedOptions(const ParamValues& params, const TechniqueMaps& maps) {
    auto baked = optionsFromArrays(maps);
    if (!baked) return baked.error();
    const BuildOptions asked = buildOptionsFrom(params);
    const BuildOptions defaults;
    if (asked.phiMaxDeg != defaults.phiMaxDeg && asked.phiMaxDeg != baked->phiMaxDeg)
        return makeError(ErrorKind::InvalidInput,
                         "{}: maps were baked with phi-max {}, not {}; bake them again",
                         maps.technique, baked->phiMaxDeg, asked.phiMaxDeg);
    if ((asked.exterior && !baked->exterior) || (asked.exteriorSlope && !baked->exteriorSlope))
        return makeError(ErrorKind::InvalidInput,
                         "{}: maps were baked for all rays (or with the all-vertex cone slope), "
                         "not as asked (exterior / exterior-slope); bake them again",
                         maps.technique);
    if (asked.isotropic && !baked->isotropic)
        return makeError(ErrorKind::InvalidInput,
                         "{}: maps were baked directional, not isotropic; bake them again",
                         maps.technique);
    return *baked;
}

}  // namespace relief::safety
