#include <relief/techniques/safety_common/safety_params.h>

namespace relief::safety {

BuildOptions buildOptionsFrom(const ParamValues& params) {
    BuildOptions o;
    o.phiMaxDeg = params.get("phi-max");
    o.isotropic = params.getInt("isotropic") != 0;
    return o;
}

MarchOptions marchOptionsFrom(const ParamValues& params, const BuildOptions& build) {
    MarchOptions m;
    m.maxSteps = params.getInt("max-steps");
    m.phiMaxDeg = build.phiMaxDeg;
    m.viewDependent = params.getInt("view-dependent") != 0;
    m.positiveDistance = params.getInt("positive-distance") != 0;
    return m;
}

std::string phiMaxViewWarning(const ParamValues& params, std::span<const Ray> rays) {
    const double phiMax = params.get("phi-max");
    const double tanPhi = tanPhiMax(phiMax);
    size_t outside = 0;
    for (const Ray& r : rays) outside += !rayWithinPhiMax(r.direction, tanPhi);
    if (outside == 0) return {};
    return fmt::format("{:.1f}% of the primary rays are outside the maps' viewing-angle restriction "
                       "(phi-max {}): they take the exact walk, which is slower (results stay exact)",
                       100.0 * double(outside) / double(rays.size()), phiMax);
}

Result<BuildOptions> bakedOptions(const ParamValues& params, const TechniqueMaps& maps) {
    auto baked = optionsFromArrays(maps);
    if (!baked) return baked.error();
    const BuildOptions asked = buildOptionsFrom(params);
    const BuildOptions defaults;
    if (asked.phiMaxDeg != defaults.phiMaxDeg && asked.phiMaxDeg != baked->phiMaxDeg)
        return makeError(ErrorKind::BadArgument,
                         "{}: maps were baked with phi-max {}, not {}; bake them again",
                         maps.technique, baked->phiMaxDeg, asked.phiMaxDeg);
    if (asked.isotropic && !baked->isotropic)
        return makeError(ErrorKind::BadArgument,
                         "{}: maps were baked directional, not isotropic; bake them again",
                         maps.technique);
    return *baked;
}

}  // namespace relief::safety
