#include <relief/techniques/safety_sd/safety_sd.h>

namespace relief {

namespace {
constexpr const char* kName = "safety-sd";
}

Result<SafetySdTracer> makeSafetySdTracer(const TechniqueInput& input) {
    auto map = safety::mapFor<safety::DistanceMap>(input, safety::distanceMapFromArrays,
                                                   safety::buildDistanceMap);
    if (!map) return map.error();
    auto& [shape, build] = *map;
    return SafetySdTracer(input.surface, safety::DistanceShape(std::move(shape)),
                          safety::marchOptionsFrom(input.params, build));
}

Result<std::unique_ptr<Tracer>> createSafetySd(const TechniqueInput& input) {
    auto tracer = makeSafetySdTracer(input);
    if (!tracer) return tracer.error();
    return makeBatchTracer(std::move(*tracer));
}

Result<TechniqueMaps> buildSafetySdMaps(const TechniqueInput& input) {
    const safety::BuildOptions build = safety::buildOptionsFrom(input.params);
    if (Status ok = safety::checkBuildOptions(*input.surface, build); !ok) return ok.error();
    return safety::distanceMapToArrays(kName, safety::buildDistanceMap(*input.surface, build),
                                       build);
}

}  // namespace relief
