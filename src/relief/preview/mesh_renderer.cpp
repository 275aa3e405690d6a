#include <relief/gl/egl_context.h>
#include <relief/gl/program.h>
#include <relief/gl/shader_library.h>
#include <relief/gl/shader_sources.h>
#include <relief/preview/mesh_renderer.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <glm/gtc/matrix_transform.hpp>

namespace relief::preview {

// The vertex array of a mesh (MeshVertex interleaved) and its index buffer; outside the
// anonymous namespace, since MeshPreview::State holds one.
struct MeshBuffers {
    gl::GlVertexArray vertexArray;
    gl::GlBuffer vertices, indices;
    GLsizei count = 0;
};

namespace {

constexpr float kCrossingHalfSide = 1.2f;
constexpr float kFarAway = 3.0e38f;  // the info target's clear value: nothing in the pixel

// The fragment shader: the library, the row's samplers and calls, the preview's main.
Result<std::string> fragmentText(const TechniqueInfo& info) {
    auto library = gl::shaderLibraryText(info.shaderFile);
    if (!library) return library.error();
    std::string samplers, arguments;
    for (const ShaderSampler& s : info.shaderSamplers) {
        samplers += fmt::format("uniform sampler2D {};\n", s.name);
        arguments += std::string(s.name) + ", ";
    }
    return fmt::format(
        "#version 330 core\n{}\n{}#define RELIEF_TRACE(uv, v, p) {}({}uv, v, p)\n"
        "#define RELIEF_SHADOW(hit, l, p) {}Shadow({}hit, l, p)\n#line 1\n{}",
        *library, samplers, info.shaderFunction, arguments, info.shaderFunction, arguments,
        gl::shaderSource("preview_fragment.glsl"));
}

GLenum wrapOf(const Surface& surface) {
    return surface.edge() == EdgeMode::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
}

int mipLevels(int width, int height) { return std::bit_width(unsigned(std::max(width, height))); }

// Trilinear, mipmapped, wrapped as the surface.
void filtered(GLuint id, const Surface& surface) {
    glGenerateTextureMipmap(id);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GLint(wrapOf(surface)));
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GLint(wrapOf(surface)));
}

gl::GlTexture colorTexture(const ImageRgb8& image, const Surface& surface) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    // RGBA storage: mipmaps are generated only for colour-renderable formats (not SRGB8, RGB32F).
    glTextureStorage2D(id, mipLevels(image.width, image.height), GL_SRGB8_ALPHA8, image.width,
                       image.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(id, 0, 0, 0, image.width, image.height, GL_RGB, GL_UNSIGNED_BYTE,
                        image.pixels.data());
    filtered(id, surface);
    return gl::GlTexture(id);
}

// Per sample, the normal of z = D·h by central differences (texel units), edges as the surface.
gl::GlTexture normalTexture(const Surface& surface) {
    const Heightfield& hf = surface.heightfield();
    const int w = hf.width, h = hf.height;
    const bool wrap = surface.edge() == EdgeMode::Repeat;
    auto at = [&](int i, int j) {
        i = wrap ? (i % w + w) % w : std::clamp(i, 0, w - 1);
        j = wrap ? (j % h + h) % h : std::clamp(j, 0, h - 1);
        return surface.depth() * hf.at(i, j);
    };
    std::vector<float> normals;
    normals.reserve(size_t(w) * size_t(h) * 3);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const vec3 n = glm::normalize(vec3(-0.5f * (at(i + 1, j) - at(i - 1, j)),
                                               -0.5f * (at(i, j + 1) - at(i, j - 1)), 1.0f));
            normals.insert(normals.end(), {n.x, n.y, n.z});
        }
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, mipLevels(w, h), GL_RGBA32F, w, h);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(id, 0, 0, 0, w, h, GL_RGB, GL_FLOAT, normals.data());
    filtered(id, surface);
    return gl::GlTexture(id);
}

MeshBuffers upload(const Mesh& mesh) {
    MeshBuffers b;
    b.vertices.upload(mesh.vertices.data(), mesh.vertices.size() * sizeof(MeshVertex),
                      GL_STATIC_DRAW);
    b.indices.upload(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t), GL_STATIC_DRAW);
    b.count = GLsizei(mesh.indices.size());
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    b.vertexArray = gl::GlVertexArray(id);
    glVertexArrayVertexBuffer(id, 0, b.vertices.id(), 0, sizeof(MeshVertex));
    glVertexArrayElementBuffer(id, b.indices.id());
    const struct {
        GLint size;
        size_t offset;
    } attributes[] = {{3, offsetof(MeshVertex, position)},
                      {3, offsetof(MeshVertex, normal)},
                      {2, offsetof(MeshVertex, uv)},
                      {4, offsetof(MeshVertex, tangent)},
                      {2, offsetof(MeshVertex, uvScale)}};
    for (GLuint k = 0; k < 5; ++k) {
        glVertexArrayAttribFormat(id, k, attributes[k].size, GL_FLOAT, GL_FALSE,
                                  GLuint(attributes[k].offset));
        glVertexArrayAttribBinding(id, k, 0);
        glEnableVertexArrayAttrib(id, k);
    }
    return b;
}

Mesh crossingSquare(float z) {
    Mesh m;
    const float s = kCrossingHalfSide;
    for (vec2 c : {vec2(-s, -s), vec2(s, -s), vec2(-s, s), vec2(s, s)})
        m.vertices.push_back({vec3(c, z), vec3(0, 0, 1), c, glm::vec4(1, 0, 0, 1), vec2(1)});
    m.indices = {0, 1, 3, 0, 3, 2};
    return m;
}

// Near and far planes around the scene (the mesh within radius 1, the crossing square within
// kSceneRadius of the centre), so the depth buffer's precision is spent on it.
glm::mat4 clipFromWorld(const Camera& camera) {
    constexpr float kSceneRadius = 1.8f;
    const float d = glm::length(camera.eye());
    const float near = std::max(0.01f * d, d - kSceneRadius), far = d + kSceneRadius;
    return glm::perspective(2.0f * std::atan(camera.halfHeight()),
                            camera.halfWidth() / camera.halfHeight(), near, far) *
           glm::lookAt(camera.eye(), camera.eye() + camera.forward(), camera.up());
}

float meanUvScale(const Mesh& mesh) {
    double sum = 0.0;
    for (const MeshVertex& v : mesh.vertices) sum += v.uvScale.x;
    return mesh.vertices.empty() ? 1.0f : float(sum / double(mesh.vertices.size()));
}

float worldDepthFrom(float meanScale, const Surface& surface, float tiles) {
    return surface.depth() / float(surface.width()) * meanScale / tiles;
}

float topOf(const Mesh& mesh) {
    float top = -kInfinity;
    for (const MeshVertex& v : mesh.vertices) top = std::max(top, v.position.z);
    return top;
}

float crossingZFrom(float top, float meanScale, const Surface& surface,
                    const MeshRenderSettings& settings) {
    const float h = settings.crossingHeight.value_or(1.0f);
    return top - (settings.midLevel - h) * worldDepthFrom(meanScale, surface, settings.tiles);
}

}  // namespace

float worldDepth(const Mesh& mesh, const Surface& surface, float tiles) {
    return worldDepthFrom(meanUvScale(mesh), surface, tiles);
}

float crossingZ(const Mesh& mesh, const Surface& surface, const MeshRenderSettings& settings) {
    return crossingZFrom(topOf(mesh), meanUvScale(mesh), surface, settings);
}

Camera meshCamera(const MeshRenderSettings& settings) {
    return Camera(settings.view, vec3(0.0f), 2.0f, settings.width, settings.height);
}

struct MeshPreview::State {
    const TechniqueInfo* info = nullptr;
    ParamValues params;
    TechniqueMaps maps;
    std::shared_ptr<const Surface> surface;
    gl::GlProgram program;
    std::vector<gl::GlTexture> textures;
    gl::GlTexture normals, colors;
    MeshBuffers mesh;
    float top = 0.0f, meanUvScale = 1.0f;  // of the mesh: its highest z, its mean |dP/du|
};

MeshPreview::MeshPreview(std::unique_ptr<State> state) : m_state(std::move(state)) {}
MeshPreview::~MeshPreview() = default;
MeshPreview::MeshPreview(MeshPreview&&) noexcept = default;
MeshPreview& MeshPreview::operator=(MeshPreview&&) noexcept = default;

Result<MeshPreview> MeshPreview::create(const TechniqueInfo& info, const ParamValues& params,
                                        const TechniqueMaps& maps,
                                        std::shared_ptr<const Surface> surface,
                                        const ImageRgb8* color) {
    if (info.shaderFunction.empty())
        return makeError(ErrorKind::Unsupported,
                         "{}: no shader-library function (docs/engine.md), so no mesh preview",
                         info.name);
    auto state = std::make_unique<State>();
    state->info = &info;
    state->params = params;
    state->maps = maps;
    state->surface = surface;
    auto fragment = fragmentText(info);
    if (!fragment) return fragment.error();
    auto program = gl::graphicsProgramFromText(
        fmt::format("mesh preview {}", info.name),
        "#version 330 core\n" + std::string(gl::shaderSource("preview_vertex.glsl")), *fragment);
    if (!program) return program.error();
    state->program = std::move(*program);
    auto textures = gl::libraryTextures(info, surface->heightfield(), maps);
    if (!textures) return textures.error();
    state->textures = std::move(*textures);
    state->normals = normalTexture(*surface);
    if (color) state->colors = colorTexture(*color, *surface);
    return MeshPreview(std::move(state));
}

void MeshPreview::setMesh(const Mesh& mesh) {
    m_state->mesh = upload(mesh);
    m_state->top = topOf(mesh);
    m_state->meanUvScale = meanUvScale(mesh);
}

void MeshPreview::draw(const Camera& camera, const MeshRenderSettings& settings) const {
    const State& st = *m_state;
    const glm::mat4 clip = clipFromWorld(camera);
    const GLuint p = st.program.id();
    glUseProgram(p);
    auto uniform = [&](const char* name) { return glGetUniformLocation(p, name); };
    glUniformMatrix4fv(uniform("clipFromWorld"), 1, GL_FALSE, &clip[0][0]);
    glUniform3fv(uniform("eye"), 1, &camera.eye().x);
    const vec3 light = glm::normalize(settings.towardsLight);
    glUniform3fv(uniform("towardsLight"), 1, &light.x);
    glUniform1i(uniform("shadows"), settings.shadows ? 1 : 0);
    glUniform1i(uniform("hasColor"), st.colors.id() ? 1 : 0);
    glUniform1f(uniform("exposure"), settings.exposure);
    glUniform1f(uniform("specular"), settings.specular);
    gl::LibraryParams lp = gl::libraryParams(*st.info, st.params, st.maps);
    lp.midLevel = settings.midLevel;
    gl::setLibraryUniforms(p, "params", *st.surface, lp);
    gl::bindLibraryTextures(p, *st.info, st.textures);
    const int unit = int(st.textures.size());
    glBindTextureUnit(GLuint(unit), st.normals.id());
    glUniform1i(uniform("normalMap"), unit);
    glBindTextureUnit(GLuint(unit + 1), st.colors.id());
    glUniform1i(uniform("colorMap"), unit + 1);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    auto drawBuffers = [&](const MeshBuffers& buffers, MeshPixel object, float tiles) {
        glUniform1f(uniform("tiles"), tiles);
        glUniform1i(uniform("object"), int(object));
        glBindVertexArray(buffers.vertexArray.id());
        glDrawElements(GL_TRIANGLES, buffers.count, GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(0);
    };
    drawBuffers(st.mesh, MeshPixel::Relief, settings.tiles);
    if (settings.crossingHeight) {
        const MeshBuffers square =
            upload(crossingSquare(crossingZFrom(st.top, st.meanUvScale, *st.surface, settings)));
        drawBuffers(square, MeshPixel::Crossing, 1.0f);
    }
    glUseProgram(0);
}

Result<MeshImage> renderMesh(const TechniqueInfo& info, const ParamValues& params,
                             const TechniqueMaps& maps, std::shared_ptr<const Surface> surface,
                             const Mesh& mesh, const ImageRgb8* color,
                             const MeshRenderSettings& settings) {
    auto context = gl::EglContext::shared();
    if (!context) return context.error();
    gl::EglContext::Scope scope(**context);
    auto preview = MeshPreview::create(info, params, maps, surface, color);
    if (!preview) return preview.error();
    preview->setMesh(mesh);

    const int w = settings.width, h = settings.height;
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    gl::GlFramebuffer framebuffer(id);
    gl::GlRenderbuffer targets[3];
    const GLenum formats[3] = {GL_RGBA8, GL_RGBA32F, GL_DEPTH_COMPONENT32F};
    const GLenum attachments[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_DEPTH_ATTACHMENT};
    for (int k = 0; k < 3; ++k) {
        GLuint rb = 0;
        glCreateRenderbuffers(1, &rb);
        targets[k] = gl::GlRenderbuffer(rb);
        glNamedRenderbufferStorage(rb, formats[k], w, h);
        glNamedFramebufferRenderbuffer(id, attachments[k], GL_RENDERBUFFER, rb);
    }
    glNamedFramebufferDrawBuffers(id, 2, attachments);
    if (glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return makeError(ErrorKind::Runtime, "mesh preview: framebuffer {}x{} incomplete", w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, id);
    glViewport(0, 0, w, h);
    const float background[4] = {0.10f, 0.11f, 0.13f, 1.0f}, nothing[4] = {kFarAway, 0, 0, 0};
    const float far = 1.0f;
    glClearBufferfv(GL_COLOR, 0, background);
    glClearBufferfv(GL_COLOR, 1, nothing);
    glClearBufferfv(GL_DEPTH, 0, &far);
    preview->draw(meshCamera(settings), settings);

    std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
    std::vector<vec4> info4(size_t(w) * size_t(h));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glNamedFramebufferReadBuffer(id, GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glNamedFramebufferReadBuffer(id, GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, info4.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (const std::string error = gl::takeGlError(); !error.empty())
        return makeError(ErrorKind::Runtime, "mesh preview {}: {}", info.name, error);

    MeshImage out{ImageRgb8(w, h), ImageF(w, h), Image<MeshPixel>(w, h)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = size_t(h - 1 - y) * size_t(w) + size_t(x);  // GL rows: bottom first
            out.color.at(x, y) = Rgb8(rgba[4 * k], rgba[4 * k + 1], rgba[4 * k + 2]);
            const vec4 i = info4[k];
            out.distance.at(x, y) = i.x >= kFarAway ? kInfinity : i.x;
            out.object.at(x, y) = MeshPixel(int(i.y + 0.5f));
        }
    return out;
}

}  // namespace relief::preview
