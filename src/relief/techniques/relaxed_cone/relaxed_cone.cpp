#include <relief/techniques/relaxed_cone/relaxed_cone.h>

namespace relief {

namespace {
// Baked maps record the variant they were built for: the published relaxed map is cone_maps'
// variant 1 (the strict-cone variant 0 was dropped: it is `cone`'s safe map, relaxed_cone.h).
constexpr int kPublishedVariant = 1;

// The published map, built now or taken from baked maps (refusing those of the dropped variant
// with a message that says so).
Result<std::shared_ptr<const ConeMap>> relaxedMapFor(const TechniqueInput& input) {
    if (input.maps) {
        auto found = input.maps->parameters.find("variant");
        if (found != input.maps->parameters.end() && found->second == "0")
            return makeError(ErrorKind::InvalidInput,
                             "relaxed-cone: these maps were baked for the strict-cone variant "
                             "(variant=0), which is gone: bake relaxed-cone again (the strict "
                             "map is cone's: bake cone)");
    }
    return coneMapFor(input, "relaxed-cone", ConeKind::FaithfulRelaxed, kPublishedVariant);
}
}  // namespace

Result<std::unique_ptr<Tracer>> createRelaxedCone(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "relaxed-cone"); !status.ok())
        return status.error();
    auto map = relaxedMapFor(input);
    if (!map) return map.error();
    const RelaxedLimits limits{input.params.getInt("max-steps"),
                               input.params.getInt("binary-steps")};
    return makeBatchTracer(RelaxedConeTracer(input.surface, std::move(*map), limits));
}

Status checkRelaxedCone(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "relaxed-cone"); !status.ok())
        return status;
    if (!input.maps) return {};
    auto map = relaxedMapFor(input);
    return map ? Status() : Status(map.error());
}

Result<TechniqueMaps> buildRelaxedConeMaps(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "relaxed-cone"); !status.ok())
        return status.error();
    return coneTechniqueMaps(input, "relaxed-cone", ConeKind::FaithfulRelaxed, kPublishedVariant);
}

}  // namespace relief
