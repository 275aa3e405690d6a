#pragma once
// Blocks that cross the C++/GLSL boundary, defined once in C++ (STYLE: "C++ and GLSL in step").
//
// A block is an X-macro list of (type, name) fields. RELIEF_GL_BLOCK turns the list into a C++
// struct whose members carry their std140 alignment, a field table with offsetof of every member,
// and a static_assert that the C++ offsets and size are exactly what std140 gives (and std430 for
// the shapes used here: scalars, vectors, vec4 arrays, mat4, with the size a multiple of 16). The
// GLSL declarations are generated from the field table (glslStruct, glslUniformBlock), so a field
// is typed once; a GL test also asks the driver for its offsets and compares them with the table.
#include <relief/core/math.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace relief::gl {

using Vec4x4 = std::array<vec4, 4>;  // 16 scalars, std140-packed (arrays stride by 16 bytes)

// GLSL spelling and std140 base alignment of the C++ types allowed in blocks.
template <class T>
struct GlslType;
#define RELIEF_GL_TYPE(T, NAME, ARRAY, ALIGN)                  \
    template <>                                               \
    struct GlslType<T> {                                      \
        static constexpr std::string_view kName = NAME;       \
        static constexpr std::string_view kArray = ARRAY;     \
        static constexpr size_t kAlign = ALIGN;               \
    };
RELIEF_GL_TYPE(float, "float", "", 4)
RELIEF_GL_TYPE(int32_t, "int", "", 4)
RELIEF_GL_TYPE(uint32_t, "uint", "", 4)
RELIEF_GL_TYPE(vec2, "vec2", "", 8)
RELIEF_GL_TYPE(ivec2, "ivec2", "", 8)
RELIEF_GL_TYPE(vec3, "vec3", "", 16)
RELIEF_GL_TYPE(vec4, "vec4", "", 16)
RELIEF_GL_TYPE(glm::mat4, "mat4", "", 16)
RELIEF_GL_TYPE(Vec4x4, "vec4", "[4]", 16)
#undef RELIEF_GL_TYPE

struct GlslField {
    std::string_view type;   // GLSL type
    std::string_view name;   // the same name in C++ and GLSL
    std::string_view array;  // "" or "[N]"
    size_t offset;           // offsetof in the C++ struct
    size_t size;
    size_t align;            // std140 base alignment
};

constexpr size_t roundUp(size_t value, size_t multiple) {
    return (value + multiple - 1) / multiple * multiple;
}

// True when every offset and the size are what std140 assigns to the same declaration.
constexpr bool followsStd140(std::span<const GlslField> fields, size_t structSize) {
    size_t offset = 0;
    for (const GlslField& f : fields) {
        offset = roundUp(offset, f.align);
        if (f.offset != offset) return false;
        offset += f.size;
    }
    return roundUp(offset, 16) == structSize;
}

// Specialized by RELIEF_GL_BLOCK: kName and kFields.
template <class Block> struct BlockLayout;

#define RELIEF_GL_MEMBER(S, type, name) alignas(::relief::gl::GlslType<type>::kAlign) type name{};
#define RELIEF_GL_FIELD(S, type, name)                                                      \
    ::relief::gl::GlslField{::relief::gl::GlslType<type>::kName, #name,                    \
                            ::relief::gl::GlslType<type>::kArray, offsetof(S, name),       \
                            sizeof(type), ::relief::gl::GlslType<type>::kAlign},

// Defines struct NAME from LIST (an X-macro taking F(S, type, name)) and its layout table.
#define RELIEF_GL_BLOCK(NAME, LIST)                                                        \
    struct alignas(16) NAME {                                                              \
        LIST(RELIEF_GL_MEMBER, NAME)                                                       \
    };                                                                                     \
    template <>                                                                            \
    struct BlockLayout<NAME> {                                                             \
        static constexpr std::string_view kName = #NAME;                                   \
        static constexpr GlslField kFields[] = {LIST(RELIEF_GL_FIELD, NAME)};              \
    };                                                                                     \
    static_assert(sizeof(NAME) % 16 == 0, #NAME ": size must be a multiple of 16");       \
    static_assert(followsStd140(BlockLayout<NAME>::kFields, sizeof(NAME)),                 \
                  #NAME ": C++ offsets differ from std140")

// "    vec3 origin;\n..." for a block or struct body.
template <class Block>
std::string glslMembers() {
    std::string text;
    for (const GlslField& f : BlockLayout<Block>::kFields)
        text += fmt::format("    {} {}{};\n", f.type, f.name, f.array);
    return text;
}

// struct NAME { ... };  (for std430 buffer records)
template <class Block>
std::string glslStruct() {
    return fmt::format("struct {} {{\n{}}};\n", BlockLayout<Block>::kName, glslMembers<Block>());
}

// layout(std140, binding = B) uniform NAME { ... } instance;
template <class Block>
std::string glslUniformBlock(std::string_view binding, std::string_view instance) {
    return fmt::format("layout(std140, binding = {}) uniform {} {{\n{}}} {};\n", binding,
                       BlockLayout<Block>::kName, glslMembers<Block>(), instance);
}

}  // namespace relief::gl
