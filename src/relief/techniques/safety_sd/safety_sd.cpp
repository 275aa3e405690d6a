#include <relief/techniques/safety_sd/safety_sd.h>

#include <relief/techniques/safety_common/safety_sampled.h>

namespace relief {

namespace {
constexpr const char* kName = "safety-sd";
}

Result<SafetySdTracer> makeSafetySdTracer(const TechniqueInput& input) {
    if (Status ok = safety::checkSampledPrecompute(input.params, input.maps); !ok) return ok.error();
    const bool sampled = safety::sampledPrecompute(input.params);
    auto map = safety::mapFor<safety::DistanceMap>(
        input, safety::distanceMapFromArrays, [sampled](const Surface& s, const safety::BuildOptions& o) {
            return safety::buildDistanceMapFor(s, o, sampled);
        });
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
    if (Status ok = safety::checkSampledPrecompute(input.params, nullptr); !ok) return ok.error();
    const bool sampled = safety::sampledPrecompute(input.params);
    TechniqueMaps maps = safety::distanceMapToArrays(
        kName, *safety::sharedDistanceMap(input, build, sampled, kName), build);
    safety::recordPrecompute(maps, sampled);
    return maps;
}

}  // namespace relief
