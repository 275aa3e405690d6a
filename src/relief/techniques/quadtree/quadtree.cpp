#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/quadtree/quadtree.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createQuadtree(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"),
                            input.params.getInt("box-surface") != 0};
    const Ascent ascent = input.params.getInt("ascend") == 0 ? Ascent::None : Ascent::Parent;
    auto pyramid = maxPyramidFor(input);  // baked (input.maps) or built now
    if (!pyramid) return pyramid.error();
    QuadtreeTracer tracer(input.surface, std::move(*pyramid), ascent, limits);
    const bool packets = ascent == Ascent::Parent && limits.maxSteps == 0 &&
                         !limits.boxSurface && pyramidBits(input.params) == 32 &&
                         packetWalkSupports(tracer.pyramid()) && packetsEnabled();
    if (packets)
        return std::unique_ptr<Tracer>(
            new PacketBatchTracer<QuadtreeTracer, walkRowPackets<Ascent::Parent, QuadtreeTracer>>(
                std::move(tracer)));
    return makeBatchTracer(std::move(tracer));
}

Result<TechniqueMaps> buildQuadtreeMaps(const TechniqueInput& input) {
    return maxPyramidMaps(input, "quadtree");
}

}  // namespace relief
