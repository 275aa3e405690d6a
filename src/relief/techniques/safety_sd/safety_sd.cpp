#include <relief/techniques/safety_sd/safety_sd.h>

namespace relief {

namespace {
constexpr const char* kName = "safety-sd";
}

Result<SafetySdTracer> makeSafetySdTracer(const TechniqueInput& input) {
    safety::BuildOptions build = safety::buildOptionsFrom(input.params);
    std::shared_ptr<const safety::DistanceMap> map;
    if (input.maps) {
        auto baked = safety::bakedOptions(input.params, *input.maps);
        if (!baked) return baked.error();
        build = *baked;
        auto loaded = safety::distanceMapFromArrays(*input.maps, input.surface->width(),
                                                    input.surface->height());
        if (!loaded) return loaded.error();
        map = std::make_shared<const safety::DistanceMap>(std::move(*loaded));
    } else {
        if (Status ok = safety::checkBuildOptions(*input.surface, build); !ok) return ok.error();
        map = std::make_shared<const safety::DistanceMap>(
            safety::buildDistanceMap(*input.surface, build));
    }
    return SafetySdTracer(input.surface, safety::DistanceShape(std::move(map)),
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
