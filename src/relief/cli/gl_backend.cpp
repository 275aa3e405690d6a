#include <relief/cli/common.h>

namespace relief::cli {

Result<std::unique_ptr<Tracer>> createGlBackendTracer(const TechniqueInfo& info,
                                                      const TechniqueInput&) {
    return makeError(ErrorKind::Unsupported, "--backend gl: this build has no GL backend ({})",
                     info.name);
}

}  // namespace relief::cli
