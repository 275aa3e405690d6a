#include <relief/gl/program.h>

#include <relief/gl/shader_interface.h>
#include <relief/gl/shader_sources.h>

#include <algorithm>
#include <regex>

namespace relief::gl {

void deleteProgram(GLuint id) { glDeleteProgram(id); }
void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteRenderbuffer(GLuint id) { glDeleteRenderbuffers(1, &id); }
void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }

void GlBuffer::ensure(size_t bytes, GLenum usage) {
    if (m_name.id() && bytes <= m_capacity) return;
    GLuint id = 0;
    glCreateBuffers(1, &id);
    m_name = GlName<deleteBuffer>(id);
    m_capacity = std::max<size_t>(bytes, 16);
    glNamedBufferData(id, GLsizeiptr(m_capacity), nullptr, usage);
}

void GlBuffer::upload(const void* data, size_t bytes, GLenum usage) {
    ensure(bytes, usage);
    glNamedBufferSubData(m_name.id(), 0, GLsizeiptr(bytes), data);
}

void GlBuffer::download(void* data, size_t bytes) const {
    glGetNamedBufferSubData(m_name.id(), 0, GLsizeiptr(bytes), data);
}

std::string takeGlError() {
    std::string last;
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR;) {
        const char* name = "GL error";
        switch (e) {
            case GL_INVALID_ENUM: name = "GL_INVALID_ENUM"; break;
            case GL_INVALID_VALUE: name = "GL_INVALID_VALUE"; break;
            case GL_INVALID_OPERATION: name = "GL_INVALID_OPERATION"; break;
            case GL_INVALID_FRAMEBUFFER_OPERATION: name = "GL_INVALID_FRAMEBUFFER_OPERATION"; break;
            case GL_OUT_OF_MEMORY: name = "GL_OUT_OF_MEMORY"; break;
        }
        last = fmt::format("{} 0x{:04X}", name, unsigned(e));
    }
    return last;
}

namespace {

// File k starts at line k·kLineStride + 1 (and source string k), so that a log line can be traced
// back to its file whether or not the driver reports source-string numbers.
constexpr int kLineStride = 100000;

struct Part {
    std::string name;
    std::string text;
};

// #version, the interface as source string 0, then each file as source string 1, 2, ...
Result<std::vector<Part>> assemble(std::initializer_list<std::string_view> files,
                                   const TechniqueInfo* technique, std::string_view extra = {},
                                   const TechniqueMaps* maps = nullptr) {
    std::vector<Part> parts;
    parts.push_back({"<generated interface>",
                     "#version 450 core\n#line 1 0\n" + glslInterface(technique, maps)});
    // A technique file may name shared files it needs with `// requires: TECH/NAME.glsl` lines
    // (e.g. the pyramid walk of quadtree, maxmip and quadtree-oriented); each goes in once,
    // before the first file that requires it.
    std::vector<std::string_view> ordered;
    auto add = [&](auto&& self, std::string_view path) -> void {
        if (std::find(ordered.begin(), ordered.end(), path) != ordered.end()) return;
        const std::string_view source = shaderSource(path);
        for (size_t at = source.find("// requires: "); at != std::string_view::npos;
             at = source.find("// requires: ", at + 1)) {
            if (at != 0 && source[at - 1] != '\n') continue;
            const size_t begin = at + 13, end = source.find('\n', begin);
            self(self, source.substr(begin, end == std::string_view::npos ? end : end - begin));
        }
        ordered.push_back(path);
    };
    for (std::string_view path : files) add(add, path);
    for (std::string_view path : ordered) {
        const std::string_view source = shaderSource(path);
        if (source.empty())
            return makeError(ErrorKind::Runtime, "GL: no embedded shader '{}' (known: {})", path,
                             [] {
                                 std::string names;
                                 for (const ShaderFile& f : shaderFiles())
                                     names += (names.empty() ? "" : ", ") + std::string(f.path);
                                 return names;
                             }());
        parts.push_back({std::string(path), ""});
    }
    for (size_t k = 1; k < parts.size(); ++k)
        parts[k].text = fmt::format("#line {} {}\n{}\n", k * kLineStride + 1, k,
                                    shaderSource(parts[k].name));
    if (!extra.empty()) {
        const size_t k = parts.size();
        parts.push_back({"<inline text>",
                         fmt::format("#line {} {}\n{}\n", k * kLineStride + 1, k, extra)});
    }
    return parts;
}

// Rewrites "0:100012(5)" (Mesa) and "0(100012)" (NVIDIA) as "exact/exact.glsl:12(5)".
std::string nameFiles(const std::string& log, const std::vector<Part>& parts) {
    auto rewrite = [&](const std::string& text, const std::regex& pattern, bool withColumn) {
        std::string out;
        auto last = text.cbegin();
        for (std::sregex_iterator it(text.begin(), text.end(), pattern), end; it != end; ++it) {
            const long line = std::stol((*it)[1].str());
            const size_t file = size_t(line / kLineStride);
            out.append(last, (*it)[0].first);
            if (line >= kLineStride && file < parts.size())
                out += withColumn ? fmt::format("{}:{}({})", parts[file].name,
                                                line % kLineStride, (*it)[2].str())
                                  : fmt::format("{}:{}", parts[file].name, line % kLineStride);
            else
                out += (*it)[0].str();
            last = (*it)[0].second;
        }
        out.append(last, text.cend());
        return out;
    };
    const std::string mesa = rewrite(log, std::regex(R"(\b\d+:(\d+)\((\d+)\))"), true);
    return rewrite(mesa, std::regex(R"(\b\d+\((\d+)\))"), false);
}

std::string legend(const std::vector<Part>& parts) {
    std::string text = "source strings:";
    for (size_t k = 0; k < parts.size(); ++k) text += fmt::format(" {} = {};", k, parts[k].name);
    return text;
}

Result<GLuint> compile(GLenum stage, std::string_view label, const std::vector<Part>& parts) {
    std::vector<const char*> strings;
    for (const Part& p : parts) strings.push_back(p.text.c_str());
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, GLsizei(strings.size()), strings.data(), nullptr);
    glCompileShader(shader);
    GLint ok = 0, length = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(size_t(std::max(length, 1)), '\0');
        glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
        glDeleteShader(shader);
        log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
        const char* kind = stage == GL_COMPUTE_SHADER   ? "compute"
                           : stage == GL_VERTEX_SHADER ? "vertex"
                                                       : "fragment";
        return makeError(ErrorKind::Runtime, "GL: {} shader of '{}' does not compile:\n{}{}", kind,
                         label, nameFiles(log, parts), legend(parts));
    }
    return shader;
}

Result<GlProgram> link(std::string_view label, std::initializer_list<GLuint> shaders) {
    const GLuint program = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(program, s);
    glLinkProgram(program);
    for (GLuint s : shaders) glDeleteShader(s);
    GLint ok = 0, length = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::string log(size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
        glDeleteProgram(program);
        return makeError(ErrorKind::Runtime, "GL: program '{}' does not link:\n{}", label,
                         log.c_str());
    }
    return GlProgram(program);
}

Result<GlProgram> linkGraphics(std::string_view label, const std::vector<Part>& vertexParts,
                               const std::vector<Part>& fragmentParts) {
    auto vertex = compile(GL_VERTEX_SHADER, label, vertexParts);
    if (!vertex) return vertex.error();
    auto fragment = compile(GL_FRAGMENT_SHADER, label, fragmentParts);
    if (!fragment) {
        glDeleteShader(*vertex);
        return fragment.error();
    }
    return link(label, {*vertex, *fragment});
}

}  // namespace

Result<GlProgram> computeProgram(std::string_view label,
                                 std::initializer_list<std::string_view> files,
                                 const TechniqueInfo* technique, const TechniqueMaps* maps) {
    auto parts = assemble(files, technique, {}, maps);
    if (!parts) return parts.error();
    auto shader = compile(GL_COMPUTE_SHADER, label, *parts);
    if (!shader) return shader.error();
    return link(label, {*shader});
}

Result<GlProgram> computeProgramFromText(std::string_view label, std::string_view text) {
    auto parts = assemble({}, nullptr, text);
    if (!parts) return parts.error();
    auto shader = compile(GL_COMPUTE_SHADER, label, *parts);
    if (!shader) return shader.error();
    return link(label, {*shader});
}

Result<GlProgram> graphicsProgramFromText(std::string_view label, std::string_view vertexText,
                                          std::string_view fragmentText) {
    return linkGraphics(label, {{"<vertex text>", std::string(vertexText)}},
                        {{"<fragment text>", std::string(fragmentText)}});
}

Result<GlProgram> graphicsProgram(std::string_view label,
                                  std::initializer_list<std::string_view> vertexFiles,
                                  std::initializer_list<std::string_view> fragmentFiles) {
    auto vertexParts = assemble(vertexFiles, nullptr);
    if (!vertexParts) return vertexParts.error();
    auto fragmentParts = assemble(fragmentFiles, nullptr);
    if (!fragmentParts) return fragmentParts.error();
    return linkGraphics(label, *vertexParts, *fragmentParts);
}

}  // namespace relief::gl
