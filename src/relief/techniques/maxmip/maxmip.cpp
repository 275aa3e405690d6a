#include <relief/techniques/maxmip/maxmip.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createMaxmip(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"), false};
    return makeBatchTracer(
        MaxmipTracer(input.surface, std::make_shared<const MaxPyramid>(*input.surface), limits));
}

}  // namespace relief
