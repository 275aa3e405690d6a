#include <relief/techniques/exact/exact.h>

namespace relief {

Status checkExact(const TechniqueInput& input) {
    if (input.params.getInt("max-steps") != 0)
        return makeError(ErrorKind::BadArgument,
                         "exact: --max-steps is not supported (the reference never stops early)");
    return {};
}

Result<std::unique_ptr<Tracer>> createExact(const TechniqueInput& input) {
    if (Status status = checkExact(input); !status) return status.error();
    return makeBatchTracer(ExactTracer(input.surface));
}

}  // namespace relief
