#include <relief/gl/shader_sources.h>

namespace relief::gl {

std::span<const ShaderFile> shaderFiles() { return {kEmbeddedShaders, kEmbeddedShaderCount}; }

std::string_view shaderSource(std::string_view relativePath) {
    for (const ShaderFile& file : shaderFiles())
        if (file.path == relativePath) return file.source;
    return {};
}

}  // namespace relief::gl
