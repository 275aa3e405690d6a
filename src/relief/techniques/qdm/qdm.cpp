#include <relief/techniques/qdm/qdm.h>
#include <relief/techniques/qdm/qdm_paper.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createQdm(const TechniqueInput& input) {
    auto map = qdmMapFor(input);
    if (!map) return map.error();
    QdmLimits limits;
    limits.maxSteps = input.params.getInt("max-steps");
    if (input.params.getInt("variant") == 1)
        return makeBatchTracer(QdmPaperTracer(input.surface, std::move(*map), limits.maxSteps));
    return makeBatchTracer(QdmTracer(input.surface, std::move(*map), limits));
}

Result<TechniqueMaps> buildQdmMaps(const TechniqueInput& input) {
    const Surface& s = *input.surface;
    const QdmBuildParams params = QdmBuildParams::from(input.params);
    TechniqueMaps maps;
    maps.technique = "qdm";
    maps.parameters = qdmMapParameters(params);
    maps.arrays.push_back(encodeQdm(s, buildQdmVariant(s, params)));
    return maps;
}

}  // namespace relief
