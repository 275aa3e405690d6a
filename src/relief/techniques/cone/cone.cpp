#include <relief/techniques/cone/cone.h>
#include <relief/techniques/cone/cone_packet.h>

namespace relief {

namespace {
void tracePackets(const ConeTracer& tracer, std::span<const Ray> rays, std::span<Hit> hits) {
    coneMarchPackets(tracer.surface(), tracer.map(), tracer.limits(), rays, hits);
}

ConeKind coneKind(int variant) {
    return variant == 0 ? ConeKind::SafeStrict : ConeKind::FaithfulStrict;
}
}  // namespace

Result<std::unique_ptr<Tracer>> createCone(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "cone"); !status.ok()) return status.error();
    const int variant = input.params.getInt("variant");
    auto map = coneMapFor(input, "cone", coneKind(variant), variant);
    if (!map) return map.error();
    ConeLimits limits;
    limits.maxSteps = input.params.getInt("max-steps");
    ConeTracer tracer(input.surface, std::move(*map), limits);
    if (packetConeMarchSupports(tracer.surface(), tracer.map()) && packetsEnabled())
        return std::unique_ptr<Tracer>(
            new PacketBatchTracer<ConeTracer, tracePackets>(std::move(tracer)));
    return makeBatchTracer(std::move(tracer));
}

Status checkCone(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "cone"); !status.ok()) return status;
    if (!input.maps) return {};
    const int variant = input.params.getInt("variant");
    auto map = coneMapFor(input, "cone", coneKind(variant), variant);
    return map ? Status() : Status(map.error());
}

Result<TechniqueMaps> buildConeMaps(const TechniqueInput& input) {
    if (Status status = checkConeParams(input.params, "cone"); !status.ok()) return status.error();
    const int variant = input.params.getInt("variant");
    return coneTechniqueMaps(input, "cone", coneKind(variant), variant);
}

}  // namespace relief
