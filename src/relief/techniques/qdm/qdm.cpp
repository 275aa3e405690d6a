#include <relief/techniques/qdm/qdm.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createQdm(const TechniqueInput& input) {
    auto map = qdmMapFor(input);
    if (!map) return map.error();
    QdmLimits limits;
    limits.maxSteps = input.params.getInt("max-steps");
    return makeBatchTracer(QdmTracer(input.surface, std::move(*map), limits));
}

Result<TechniqueMaps> buildQdmMaps(const TechniqueInput& input) {
    const Surface& s = *input.surface;
    const QdmBuildParams params = QdmBuildParams::from(input.params);
    TechniqueMaps maps;
    maps.technique = "qdm";
    maps.parameters = qdmMapParameters(params);
    maps.arrays.push_back(encodeQdm(s, buildQdm(s, params)));
    return maps;
}

}  // namespace relief
