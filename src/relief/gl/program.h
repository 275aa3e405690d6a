#pragma once
// GL programs assembled from embedded sources: "#version 450 core", the generated interface
// (shader_interface.h), then the listed files (each preceded by the files it names on
// `// requires: TECH/NAME.glsl` lines, once), each opened with `#line 1 N` so that a compile
// log's "N:line" points into file N; the error lists the files by number.
//
// GL objects here must be created and destroyed while an EglContext::Scope is held.
#include <relief/core/error.h>
#include <relief/techniques/technique.h>

#include <epoxy/gl.h>

#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace relief::gl {

// Owns one GL name; `destroy` is glDeleteProgram, glDeleteBuffers... for that kind.
template <void (*Destroy)(GLuint)>
class GlName {
public:
    GlName() = default;
    explicit GlName(GLuint id) : m_id(id) {}
    ~GlName() { reset(); }
    GlName(GlName&& other) noexcept : m_id(std::exchange(other.m_id, 0)) {}
    GlName& operator=(GlName&& other) noexcept {
        if (this != &other) {
            reset();
            m_id = std::exchange(other.m_id, 0);
        }
        return *this;
    }
    GLuint id() const { return m_id; }
    void reset() {
        if (m_id) Destroy(m_id);
        m_id = 0;
    }

private:
    GLuint m_id = 0;
};

void deleteProgram(GLuint id);
void deleteBuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteRenderbuffer(GLuint id);
void deleteTexture(GLuint id);

using GlProgram = GlName<deleteProgram>;
using GlVertexArray = GlName<deleteVertexArray>;
using GlFramebuffer = GlName<deleteFramebuffer>;
using GlRenderbuffer = GlName<deleteRenderbuffer>;
using GlTexture = GlName<deleteTexture>;

// A storage buffer that grows on demand (glNamedBufferData, GL_DYNAMIC_* usage).
class GlBuffer {
public:
    GlBuffer() = default;
    void ensure(size_t bytes, GLenum usage = GL_DYNAMIC_DRAW);
    void upload(const void* data, size_t bytes, GLenum usage = GL_DYNAMIC_DRAW);
    void download(void* data, size_t bytes) const;
    GLuint id() const { return m_name.id(); }
    size_t capacity() const { return m_capacity; }

private:
    GlName<deleteBuffer> m_name;
    size_t m_capacity = 0;
};

// A uniform buffer holding one std140 block.
template <class Block>
void uploadBlock(GlBuffer& buffer, const Block& block) {
    buffer.upload(&block, sizeof(Block));
}

// Compiles and links a compute program from `files` (paths as in shaderSource), after the
// generated interface for `technique` (its kParam<Name> constants) and its `maps` (the map
// declarations of shader_interface.h), or none.
Result<GlProgram> computeProgram(std::string_view label,
                                 std::initializer_list<std::string_view> files,
                                 const TechniqueInfo* technique = nullptr,
                                 const TechniqueMaps* maps = nullptr);

// Same, for a vertex + fragment pair.
Result<GlProgram> graphicsProgram(std::string_view label,
                                  std::initializer_list<std::string_view> vertexFiles,
                                  std::initializer_list<std::string_view> fragmentFiles);

// Compiles a vertex + fragment pair from literal GLSL as given: each text carries its own
// #version and nothing is prepended (the engine shader library's tests, GLSL 3.30 core).
Result<GlProgram> graphicsProgramFromText(std::string_view label, std::string_view vertexText,
                                          std::string_view fragmentText);

// Compiles a compute program from literal GLSL after the generated interface (tests).
Result<GlProgram> computeProgramFromText(std::string_view label, std::string_view text);

// The most recent GL error as "GL_INVALID_OPERATION 0x0502", or "" when none; clears them all.
std::string takeGlError();

}  // namespace relief::gl
