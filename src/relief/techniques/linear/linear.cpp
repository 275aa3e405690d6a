#include <relief/techniques/linear/linear.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createLinear(const TechniqueInput& input) {
    return makeBatchTracer(LinearTracer(input.surface, input.params.getInt("max-steps"),
                                        input.params.getInt("binary-steps")));
}

}  // namespace relief
