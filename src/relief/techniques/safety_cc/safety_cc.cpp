#include <relief/techniques/safety_cc/safety_cc.h>

#include <relief/techniques/safety_cc/safety_cc_packet.h>
#include <relief/techniques/safety_common/safety_sampled.h>

namespace relief {

namespace {

constexpr const char* kName = "safety-cc";

// The slanted planes over the exact or (precompute=1) sampled radii.
safety::CylinderConeMap buildCone(const Surface& surface, const safety::BuildOptions& build,
                                  bool sampled) {
    return safety::buildConeMap(surface, safety::buildDistanceMapFor(surface, build, sampled), build);
}

void tracePackets(const SafetyCcTracer& tracer, std::span<const Ray> rays, std::span<Hit> hits) {
    safetyCcMarchPackets(tracer, rays, hits);
}

}  // namespace

Result<SafetyCcTracer> makeSafetyCcTracer(const TechniqueInput& input) {
    if (Status ok = safety::checkSampledPrecompute(input.params, input.maps); !ok) return ok.error();
    const bool sampled = safety::sampledPrecompute(input.params);
    auto map = safety::mapFor<safety::CylinderConeMap>(
        input, safety::coneMapFromArrays,
        [sampled](const Surface& s, const safety::BuildOptions& o) { return buildCone(s, o, sampled); });
    if (!map) return map.error();
    auto& [shape, build] = *map;
    return SafetyCcTracer(input.surface, safety::ConeShape(std::move(shape)),
                          safety::marchOptionsFrom(input.params, build));
}

Result<std::unique_ptr<Tracer>> createSafetyCc(const TechniqueInput& input) {
    auto tracer = makeSafetyCcTracer(input);
    if (!tracer) return tracer.error();
    if (packetSafetyCcSupports(*tracer) && packetsEnabled())
        return std::unique_ptr<Tracer>(
            new PacketBatchTracer<SafetyCcTracer, tracePackets>(std::move(*tracer)));
    return makeBatchTracer(std::move(*tracer));
}

Result<TechniqueMaps> buildSafetyCcMaps(const TechniqueInput& input) {
    const safety::BuildOptions build = safety::buildOptionsFrom(input.params);
    if (Status ok = safety::checkBuildOptions(*input.surface, build); !ok) return ok.error();
    if (Status ok = safety::checkSampledPrecompute(input.params, nullptr); !ok) return ok.error();
    const bool sampled = safety::sampledPrecompute(input.params);
    // Straight into the arrays (the map and its arrays are never held together); the radii
    // are safety-sd's distances, shared when the same bake builds both.
    TechniqueMaps maps = safety::buildConeArrays(
        kName, *input.surface, *safety::sharedDistanceMap(input, build, sampled, kName), build);
    safety::recordPrecompute(maps, sampled);
    return maps;
}

}  // namespace relief
