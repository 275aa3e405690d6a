#include <relief/techniques/exact/exact.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createExact(const TechniqueInput& input) {
    if (input.params.getInt("max-steps") != 0)
        return makeError(ErrorKind::BadArgument,
                         "exact: --max-steps is not supported (the reference never stops early)");
    return makeBatchTracer(ExactTracer(input.surface));
}

}  // namespace relief
