#include <relief/gl/shader_library.h>
#include <relief/gl/shader_sources.h>

#include <algorithm>
#include <bit>

namespace relief::gl {

Result<std::string> shaderLibraryText(std::string_view file) {
    std::vector<std::string> ordered;
    std::string missing;
    auto add = [&](auto&& self, const std::string& name) -> void {
        if (std::find(ordered.begin(), ordered.end(), name) != ordered.end()) return;
        const std::string_view text = shaderSource("library/" + name);
        if (text.empty()) {
            missing = name;
            return;
        }
        for (size_t at = text.find("\n// requires: "); at != std::string_view::npos;
             at = text.find("\n// requires: ", at + 1)) {
            const size_t begin = at + 14;
            self(self, std::string(text.substr(begin, text.find('\n', begin) - begin)));
        }
        ordered.push_back(name);
    };
    add(add, "common.glsl");
    add(add, std::string(file));
    if (!missing.empty())
        return makeError(ErrorKind::Runtime, "shader library: {} is not embedded", missing);
    std::string all;
    for (const std::string& name : ordered)
        all += std::string(shaderSource("library/" + name)) + "\n";
    return all;
}

LibraryParams libraryParams(const TechniqueInfo& info, const ParamValues& params,
                            const TechniqueMaps& maps) {
    LibraryParams lp;
    if (const ParamSpec* cap = paramWithRole(info, ParamRole::IterationCap))
        lp.maxSteps = params.getInt(cap->name);
    if (params.has("binary-steps")) lp.binarySteps = params.getInt("binary-steps");
    if (params.has("ascend")) lp.ascend = params.getInt("ascend");
    auto mapParam = [&](const char* key, double fallback) {
        auto found = maps.parameters.find(key);
        return found == maps.parameters.end() ? fallback : std::stod(found->second);
    };
    lp.bits = int(mapParam("bits", 32));
    lp.sqrtRatio = int(mapParam("sqrt", 0));
    lp.coneMax = float(mapParam("cone-max", 1.0));
    lp.maxDistance = info.name == "qdm" ? float(mapParam("max-distance", 0.0)) : 0.0f;
    lp.phiMax = float(mapParam("phi-max", 90.0));
    lp.exterior = int(mapParam("exterior", 0));
    lp.isotropic = int(mapParam("isotropic", 0));
    // The map's variant picks the tracer (qdm: 1 = the paper's map and Algorithm 1).
    lp.variant = info.name == "qdm" ? int(mapParam("variant", 0)) : 0;
    if (params.has("view-dependent")) lp.viewDependent = params.getInt("view-dependent");
    if (params.has("positive-distance")) lp.positiveDistance = params.getInt("positive-distance");
    return lp;
}

void setLibraryUniforms(GLuint program, std::string_view name, const Surface& surface,
                        const LibraryParams& lp) {
    const std::string prefix = std::string(name) + ".";
    auto at = [&](const char* field) {
        return glGetUniformLocation(program, (prefix + field).c_str());
    };
    glUniform2f(at("mapSize"), float(surface.width()), float(surface.height()));
    glUniform1f(at("depth"), surface.depth());
    glUniform1f(at("midLevel"), lp.midLevel);
    glUniform1i(at("edge"), surface.edge() == EdgeMode::Clamp ? 0 : 1);
    glUniform1i(at("maxSteps"), lp.maxSteps);
    glUniform1i(at("binarySteps"), lp.binarySteps);
    glUniform1i(at("bits"), lp.bits);
    glUniform1i(at("sqrtRatio"), lp.sqrtRatio);
    glUniform1f(at("coneMax"), lp.coneMax);
    glUniform1i(at("ascend"), lp.ascend);
    glUniform1f(at("maxZ"), surface.maxZ());
    glUniform1f(at("maxDistance"), lp.maxDistance);
    glUniform1f(at("phiMax"), lp.phiMax);
    glUniform1i(at("exterior"), lp.exterior);
    glUniform1i(at("viewDependent"), lp.viewDependent);
    glUniform1i(at("positiveDistance"), lp.positiveDistance);
    glUniform1i(at("isotropic"), lp.isotropic);
    glUniform1i(at("variant"), lp.variant);
}

namespace {

const GLenum kFloatInternal[] = {GL_R32F, GL_RG32F, GL_RGB32F, GL_RGBA32F};
const GLenum kFloatFormat[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};

// A pyramid's levels "<stem><k>", "<stem><k+1>", ... as the mip levels 0, 1, ... of one float
// texture, level 0 padded to powers of two so that every GL mip level holds its pyramid level.
Result<GlTexture> mipChainTexture(const TechniqueMaps& maps, std::string_view first) {
    const size_t digits = first.find_last_not_of("0123456789") + 1;
    const std::string stem(first.substr(0, digits));
    std::vector<const MapArray*> levels;
    for (const MapArray* a;
         (a = maps.find(stem + std::to_string(std::stoi(std::string(first.substr(digits))) +
                                              int(levels.size()))));)
        levels.push_back(a);
    if (levels.empty())
        return makeError(ErrorKind::InvalidInput, "maps of {}: no array {}", maps.technique, first);
    const int channels = levels[0]->channels;
    auto padded = [](int n) { return 1 << std::bit_width(unsigned(n - 1)); };
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, GLsizei(levels.size()), kFloatInternal[channels - 1],
                       padded(levels[0]->width), padded(levels[0]->height));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (size_t l = 0; l < levels.size(); ++l)
        glTextureSubImage2D(id, GLint(l), 0, 0, levels[l]->width, levels[l]->height,
                            kFloatFormat[channels - 1], GL_FLOAT, levels[l]->data.data());
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, GLint(levels.size()) - 1);
    return GlTexture(id);
}

}  // namespace

GlTexture floatTexture(int width, int height, int channels, const float* data) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, 1, kFloatInternal[channels - 1], width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (data)
        glTextureSubImage2D(id, 0, 0, 0, width, height, kFloatFormat[channels - 1], GL_FLOAT, data);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return GlTexture(id);
}

Result<std::vector<GlTexture>> libraryTextures(const TechniqueInfo& info, const Heightfield& hf,
                                               const TechniqueMaps& maps) {
    std::vector<GlTexture> textures;
    for (const ShaderSampler& s : info.shaderSamplers) {
        if (s.array.empty()) {
            textures.push_back(floatTexture(hf.width, hf.height, 1, hf.samples.data()));
        } else if (s.mipChain) {
            auto texture = mipChainTexture(maps, s.array);
            if (!texture) return texture.error();
            textures.push_back(std::move(*texture));
        } else {
            const MapArray* a = maps.find(std::string(s.array));
            if (!a && !s.fallback.empty()) a = maps.find(std::string(s.fallback));
            if (!a)
                return makeError(ErrorKind::InvalidInput, "maps of {}: no array {}", info.name,
                                 s.array);
            textures.push_back(floatTexture(a->width, a->height, a->channels, a->data.data()));
        }
    }
    return textures;
}

void bindLibraryTextures(GLuint program, const TechniqueInfo& info,
                         const std::vector<GlTexture>& textures, int firstUnit) {
    for (size_t k = 0; k < textures.size(); ++k) {
        const GLint unit = firstUnit + GLint(k);
        glBindTextureUnit(GLuint(unit), textures[k].id());
        glUniform1i(glGetUniformLocation(program, std::string(info.shaderSamplers[k].name).c_str()),
                    unit);
    }
}

}  // namespace relief::gl
