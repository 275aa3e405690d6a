#include <relief/techniques/safety_cc/safety_cc.h>

namespace relief {

namespace {

constexpr const char* kName = "safety-cc";

safety::CylinderConeMap buildCone(const Surface& surface, const safety::BuildOptions& build) {
    return safety::buildConeMap(surface, safety::buildDistanceMap(surface, build), build);
}

}  // namespace

Result<SafetyCcTracer> makeSafetyCcTracer(const TechniqueInput& input) {
    safety::BuildOptions build = safety::buildOptionsFrom(input.params);
    std::shared_ptr<const safety::CylinderConeMap> map;
    if (input.maps) {
        auto baked = safety::bakedOptions(input.params, *input.maps);
        if (!baked) return baked.error();
        build = *baked;
        auto loaded = safety::coneMapFromArrays(*input.maps, input.surface->width(),
                                                input.surface->height());
        if (!loaded) return loaded.error();
        map = std::make_shared<const safety::CylinderConeMap>(std::move(*loaded));
    } else {
        if (Status ok = safety::checkBuildOptions(*input.surface, build); !ok) return ok.error();
        map = std::make_shared<const safety::CylinderConeMap>(buildCone(*input.surface, build));
    }
    return SafetyCcTracer(input.surface, safety::ConeShape(std::move(map)),
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
