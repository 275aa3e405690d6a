#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/maxmip/maxmip.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createMaxmip(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"),
                            input.params.getInt("box-surface") != 0};
    auto pyramid = maxPyramidFor(input);  // baked (input.maps) or built now
    if (!pyramid) return pyramid.error();
    MaxmipTracer tracer(input.surface, std::move(*pyramid), limits);
    const bool packets = limits.maxSteps == 0 && !limits.boxSurface &&
                         pyramidBits(input.params) == 32 && packetWalkSupports(tracer.pyramid()) &&
                         packetsEnabled();
    if (packets)
        return std::unique_ptr<Tracer>(
            new PacketBatchTracer<MaxmipTracer, walkRowPackets<Ascent::Ancestor, MaxmipTracer>>(
                std::move(tracer)));
    return makeBatchTracer(std::move(tracer));
}

}  // namespace relief
