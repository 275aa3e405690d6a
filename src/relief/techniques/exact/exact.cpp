#include <relief/surface/cell_walk_packet.h>
#include <relief/techniques/exact/exact.h>

namespace relief {

namespace {
void tracePackets(const ExactTracer& tracer, std::span<const Ray> rays, std::span<Hit> hits) {
    // A packet's setup buys little for a few rays (the reference traced ray by ray in tests):
    // short batches stay scalar, with the same hits.
    if (rays.size() < 8) {
        for (size_t k = 0; k < rays.size(); ++k) hits[k] = tracer.trace(rays[k]);
        return;
    }
    cellsHitPackets(tracer.surface(), rays, hits);
}
}  // namespace

Status checkExact(const TechniqueInput& input) {
    if (input.params.getInt("max-steps") != 0)
        return makeError(ErrorKind::BadArgument,
                         "exact: --max-steps is not supported (the reference never stops early)");
    return {};
}

Result<std::unique_ptr<Tracer>> createExact(const TechniqueInput& input) {
    if (Status status = checkExact(input); !status) return status.error();
    ExactTracer tracer(input.surface);
    if (packetCellWalkSupports(tracer.surface()) && packetsEnabled())
        return std::unique_ptr<Tracer>(
            new PacketBatchTracer<ExactTracer, tracePackets>(std::move(tracer)));
    return makeBatchTracer(std::move(tracer));
}

}  // namespace relief
