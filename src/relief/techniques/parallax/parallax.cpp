#include <relief/techniques/parallax/parallax.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createParallax(const TechniqueInput& input) {
    return makeBatchTracer(ParallaxTracer(input.surface));
}

}  // namespace relief
