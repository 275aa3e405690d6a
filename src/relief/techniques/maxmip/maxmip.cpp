#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/maxmip/maxmip.h>

namespace relief {
namespace {

// The default walk over a batch in SIMD packets (the same hits as MaxmipTracer::trace).
class MaxmipPacketTracer final : public Tracer {
public:
    explicit MaxmipPacketTracer(MaxmipTracer impl) : m_impl(std::move(impl)) {}
    void traceBatch(std::span<const Ray> rays, std::span<Hit> hits) const override {
        walkPyramidPackets(m_impl.surface(), m_impl.pyramid(), rays, hits, Ascent::Ancestor);
    }

private:
    MaxmipTracer m_impl;
};

}  // namespace

Result<std::unique_ptr<Tracer>> createMaxmip(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"),
                            input.params.getInt("box-surface") != 0};
    auto pyramid = maxPyramidFor(input);  // baked (input.maps) or built now
    if (!pyramid) return pyramid.error();
    MaxmipTracer tracer(input.surface, std::move(*pyramid), limits);
    const bool packets = limits.maxSteps == 0 && !limits.boxSurface &&
                         pyramidBits(input.params) == 32 && packetWalkSupports(tracer.pyramid()) &&
                         packetWalkEnabled();
    if (packets) return std::unique_ptr<Tracer>(new MaxmipPacketTracer(std::move(tracer)));
    return makeBatchTracer(std::move(tracer));
}

}  // namespace relief
