#include <relief/cli/common.h>
#include <relief/gl/gl_tracer.h>

namespace relief::cli {

Result<std::unique_ptr<Tracer>> createGlBackendTracer(const TechniqueInfo& info,
                                                      const TechniqueInput& input) {
    if (info.glsl.empty())
        return makeError(ErrorKind::Unsupported, "--backend gl: '{}' has no GLSL tracer yet", info.name);
    return createGlTracer(info, input);
}

}  // namespace relief::cli
