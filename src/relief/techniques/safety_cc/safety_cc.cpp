#include <relief/techniques/safety_cc/safety_cc.h>

namespace relief {

namespace {

constexpr const char* kName = "safety-cc";

safety::CylinderConeMap buildCone(const Surface& surface, const safety::BuildOptions& build) {
    return safety::buildConeMap(surface, safety::buildDistanceMap(surface, build), build);
}

}  // namespace

Result<SafetyCcTracer> makeSafetyCcTracer(const TechniqueInput& input) {
    auto map = safety::mapFor<safety::CylinderConeMap>(input, safety::coneMapFromArrays, buildCone);
    if (!map) return map.error();
    auto& [shape, build] = *map;
    return SafetyCcTracer(input.surface, safety::ConeShape(std::move(shape)),
                          safety::marchOptionsFrom(input.params, build));
}

Result<std::unique_ptr<Tracer>> createSafetyCc(const TechniqueInput& input) {
    auto tracer = makeSafetyCcTracer(input);
    if (!tracer) return tracer.error();
    return makeBatchTracer(std::move(*tracer));
}

Result<TechniqueMaps> buildSafetyCcMaps(const TechniqueInput& input) {
    const safety::BuildOptions build = safety::buildOptionsFrom(input.params);
    if (Status ok = safety::checkBuildOptions(*input.surface, build); !ok) return ok.error();
    return safety::coneMapToArrays(kName, buildCone(*input.surface, build), build);
}

}  // namespace relief
