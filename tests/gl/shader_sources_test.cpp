// Embedded shader sources and program assembly: every registry row's `glsl` is embedded, every
// technique shader belongs to a row, every such program compiles, and a compile error names the
// file it happened in.
#include "gl_test_support.h"

#include <relief/gl/program.h>
#include <relief/gl/shader_sources.h>
#include <relief/techniques/registry.h>

namespace relief::gl {
namespace {

TEST(GlShaders, CommonFilesAreEmbedded) {
    for (std::string_view path : {"common_types.glsl", "common_surface.glsl",
                                  "common_cell_intersect.glsl", "common_camera.glsl",
                                  "main_rays.glsl", "main_camera.glsl", "mesh_vertex.glsl",
                                  "mesh_fragment.glsl"})
        EXPECT_FALSE(shaderSource(path).empty()) << path;
    EXPECT_TRUE(shaderSource("no_such_file.glsl").empty());
    EXPECT_NE(shaderSource("exact/exact.glsl").find("Hit trace(Ray ray)"), std::string_view::npos);
}

TEST(GlShaders, RegistryRowsAndTechniqueShadersMatch) {
    for (const TechniqueInfo& info : techniques()) {
        if (info.glsl.empty()) continue;
        EXPECT_FALSE(shaderSource(info.glsl).empty())
            << info.name << ": glsl = \"" << info.glsl << "\" is not embedded";
        EXPECT_EQ(info.glsl.substr(0, info.name.size() + 1), std::string(info.name) + "/")
            << info.name << ": its GLSL lives in its own folder";
    }
    // A technique shader no row points at is a row someone forgot to fill.
    for (const ShaderFile& file : shaderFiles()) {
        if (file.path.find('/') == std::string_view::npos) continue;  // common or entry point
        bool used = false;
        for (const TechniqueInfo& info : techniques()) used = used || info.glsl == file.path;
        EXPECT_TRUE(used) << file.path << " is embedded but no registry row has it as glsl";
    }
}

TEST(GlShaders, EveryTechniqueProgramCompiles) {
    RELIEF_REQUIRE_GL();
    auto context = *EglContext::shared();
    EglContext::Scope scope(*context);
    for (const TechniqueInfo& info : techniques()) {
        if (info.glsl.empty()) continue;
        for (std::string_view entry : {"main_rays.glsl", "main_camera.glsl"}) {
            auto program = computeProgram(info.name,
                                          {"common_types.glsl", "common_surface.glsl",
                                           "common_cell_intersect.glsl", "common_camera.glsl",
                                           info.glsl, entry},
                                          &info);
            EXPECT_TRUE(program) << program.error().message;
        }
    }
    auto mesh = graphicsProgram("mesh", {"mesh_vertex.glsl"}, {"mesh_fragment.glsl"});
    EXPECT_TRUE(mesh) << mesh.error().message;
}

TEST(GlShaders, CompileErrorsNameTheFile) {
    RELIEF_REQUIRE_GL();
    auto context = *EglContext::shared();
    EglContext::Scope scope(*context);
    auto program = computeProgramFromText("broken", "layout(local_size_x = 1) in;\n"
                                                    "void main() { undeclared = 1; }\n");
    ASSERT_FALSE(program);
    EXPECT_EQ(program.error().kind, ErrorKind::Runtime);
    const std::string& message = program.error().message;
    EXPECT_NE(message.find("'broken'"), std::string::npos) << message;
    EXPECT_NE(message.find("undeclared"), std::string::npos) << message;
    EXPECT_NE(message.find("<inline text>:2"), std::string::npos) << message;
    EXPECT_NE(message.find("1 = <inline text>"), std::string::npos) << message;
    std::printf("%s\n", message.c_str());

    auto missing = computeProgram("missing", {"common_types.glsl", "nope/nope.glsl"});
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("nope/nope.glsl"), std::string::npos);
}

}  // namespace
}  // namespace relief::gl
