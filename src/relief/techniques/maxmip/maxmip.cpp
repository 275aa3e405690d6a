#include <relief/techniques/maxmip/maxmip.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createMaxmip(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"),
                            input.params.getInt("box-surface") != 0};
    auto pyramid = maxPyramidFor(input);  // baked (input.maps) or built now
    if (!pyramid) return pyramid.error();
    return makeBatchTracer(MaxmipTracer(input.surface, std::move(*pyramid), limits));
}

}  // namespace relief
