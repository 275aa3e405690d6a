#pragma once
// The engine shader library (shaders/relief/, docs/engine.md) inside relief's own GL programs:
// a row's file after common.glsl and the files its `// requires:` lines name (embedded at build
// time under "library/NAME.glsl"), the ReliefParams a row's parameters and maps give, and its
// samplers' textures (float, nearest: the library reads them with texelFetch). The library's GL
// tests and the mesh preview (src/relief/preview/) draw through this.
//
// GL objects here must be created and destroyed while an EglContext::Scope is held.
#include <relief/core/error.h>
#include <relief/gl/program.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <string>
#include <string_view>
#include <vector>

namespace relief::gl {

// common.glsl, then `file` (a row's shaderFile) after the files it requires, each once; an
// Internal error when a file is not embedded.
Result<std::string> shaderLibraryText(std::string_view file);

// The struct ReliefParams fields that are not the surface's (common.glsl).
struct LibraryParams {
    float midLevel = 1.0f;
    int maxSteps = 0, binarySteps = 0, bits = 32, sqrtRatio = 0, ascend = 1;
    float coneMax = 1.0f, maxDistance = 0.0f, phiMax = 90.0f;
    int exterior = 0, viewDependent = 0, positiveDistance = 0, isotropic = 0, variant = 0;
};

// A row's resolved parameters and its maps' own (bits, cone-max, phi-max...) as ReliefParams.
LibraryParams libraryParams(const TechniqueInfo& info, const ParamValues& params,
                            const TechniqueMaps& maps);

// Sets the uniform struct `name` (a ReliefParams) of the current program `program`.
void setLibraryUniforms(GLuint program, std::string_view name, const Surface& surface,
                        const LibraryParams& lp);

// One texture per sampler of the row's function (info.shaderSamplers, in order), from the
// heightfield and the maps; InvalidInput naming the array the maps lack.
Result<std::vector<GlTexture>> libraryTextures(const TechniqueInfo& info, const Heightfield& hf,
                                               const TechniqueMaps& maps);

// Binds `textures` to units firstUnit, firstUnit + 1, ... and their samplers to those units.
void bindLibraryTextures(GLuint program, const TechniqueInfo& info,
                         const std::vector<GlTexture>& textures, int firstUnit = 0);

// A width×height float texture of 1 to 4 channels (null data: uninitialised), nearest.
GlTexture floatTexture(int width, int height, int channels, const float* data);

}  // namespace relief::gl
