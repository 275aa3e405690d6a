#include <relief/techniques/relaxed_cone/relaxed_cone.h>

namespace relief {

namespace {
ConeKind relaxedKind(int variant) {
    return variant == 0 ? ConeKind::SafeStrict : ConeKind::FaithfulRelaxed;
}
}  // namespace

Result<std::unique_ptr<Tracer>> createRelaxedCone(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "relaxed-cone"); !status.ok())
        return status.error();
    const int variant = input.params.getInt("variant");
    auto map = coneMapFor(input, "relaxed-cone", relaxedKind(variant), variant);
    if (!map) return map.error();
    const RelaxedLimits limits{input.params.getInt("max-steps"),
                               input.params.getInt("binary-steps")};
    return makeBatchTracer(RelaxedConeTracer(input.surface, std::move(*map), limits));
}

Status checkRelaxedCone(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "relaxed-cone"); !status.ok())
        return status;
    if (!input.maps) return {};
    const int variant = input.params.getInt("variant");
    auto map = coneMapFor(input, "relaxed-cone", relaxedKind(variant), variant);
    return map ? Status() : Status(map.error());
}

Result<TechniqueMaps> buildRelaxedConeMaps(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "relaxed-cone"); !status.ok())
        return status.error();
    const int variant = input.params.getInt("variant");
    return coneTechniqueMaps(input, "relaxed-cone", relaxedKind(variant), variant);
}

}  // namespace relief
