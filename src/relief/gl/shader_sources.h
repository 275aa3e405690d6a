#pragma once
// Shader sources embedded at build time (embed_shaders.cmake): every src/relief/gl/shaders/*.glsl
// under its file name ("common_surface.glsl"), every src/relief/surface/*.glsl under
// "surface/NAME.glsl" and every src/relief/techniques/*/*.glsl under "TECH/NAME.glsl"
// ("exact/exact.glsl", the value of TechniqueInfo::glsl); the engine shader library
// (shaders/relief/*.glsl) under "library/NAME.glsl" (gl/shader_library.h).
#include <cstddef>
#include <span>
#include <string_view>

namespace relief::gl {

struct ShaderFile {
    std::string_view path;
    std::string_view source;
};

// The source of `relativePath`, or an empty view when there is no such file.
std::string_view shaderSource(std::string_view relativePath);
std::span<const ShaderFile> shaderFiles();

// Defined in the generated file.
extern const ShaderFile kEmbeddedShaders[];
extern const size_t kEmbeddedShaderCount;

}  // namespace relief::gl
