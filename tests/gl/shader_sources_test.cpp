// Embedded shader sources and program assembly: every registry row's `glsl` is embedded, every
// technique shader belongs to a row, every such program compiles, and a compile error names the
// file it happened in.
#include <support/gl_test_support.h>

#include <relief/gl/program.h>
#include <relief/gl/shader_interface.h>
#include <relief/gl/shader_sources.h>
#include <relief/techniques/registry.h>

#include <algorithm>
#include <optional>

namespace relief::gl {
namespace {

TEST(GlShaders, CommonFilesAreEmbedded) {
    for (std::string_view path : {"common_types.glsl", "common_surface.glsl",
                                  "common_cell_intersect.glsl", "common_camera.glsl",
                                  "main_rays.glsl", "main_camera.glsl", "mesh_vertex.glsl",
                                  "mesh_fragment.glsl", "surface/cell_cursor.glsl",
                                  "surface/cell_walk.glsl", "preview_vertex.glsl",
                                  "preview_fragment.glsl", "library/common.glsl",
                                  "library/cone.glsl"})
        EXPECT_FALSE(shaderSource(path).empty()) << path;
    EXPECT_TRUE(shaderSource("no_such_file.glsl").empty());
    EXPECT_NE(shaderSource("exact/exact.glsl").find("Hit trace(Ray ray)"), std::string_view::npos);
}

TEST(GlShaders, RegistryRowsAndTechniqueShadersMatch) {
    for (const TechniqueInfo& info : techniques()) {
        if (info.glsl.empty()) continue;
        EXPECT_FALSE(shaderSource(info.glsl).empty())
            << info.name << ": glsl = \"" << info.glsl << "\" is not embedded";
        std::string folder(info.name);  // "safety-sd" lives in safety_sd/
        std::replace(folder.begin(), folder.end(), '-', '_');
        EXPECT_EQ(info.glsl.substr(0, folder.size() + 1), folder + "/")
            << info.name << ": its GLSL lives in its own folder";
    }
    // A technique shader no row points at (directly or by a `// requires:` line of a row's
    // file) is a row someone forgot to fill.
    for (const ShaderFile& file : shaderFiles()) {
        if (file.path.find('/') == std::string_view::npos) continue;  // common or entry point
        if (file.path.starts_with("surface/")) continue;  // the surface's twins, shared by rows
        if (file.path.starts_with("library/")) continue;  // the engine library: its own tests
        bool used = false;
        for (const TechniqueInfo& info : techniques())
            used = used || info.glsl == file.path ||
                   (!info.glsl.empty() &&
                    shaderSource(info.glsl).find("// requires: " + std::string(file.path)) !=
                        std::string_view::npos);
        EXPECT_TRUE(used) << file.path << " is embedded but no registry row has it as glsl";
    }
}

// A row's program declares the constants its row carries (glslConstants), and no other row's.
TEST(GlShaders, InterfaceDeclaresTheRowsConstantsOnly) {
    for (const TechniqueInfo& info : techniques()) {
        const std::string text = glslInterface(&info);
        for (const GlslConstant& c : info.glslConstants)
            EXPECT_NE(text.find(fmt::format("const {} {} = ", c.integer ? "int" : "float", c.name)),
                      std::string::npos)
                << info.name << ": " << c.name;
    }
    const std::string cone = glslInterface(findTechnique("cone"));
    EXPECT_NE(cone.find("const float kConeStall = 0.100000001;"), std::string::npos) << cone;
    EXPECT_NE(cone.find("const float kConeDecodeMargin = 9.53674316e-07;"), std::string::npos);
    EXPECT_EQ(cone.find("kWalkSlack"), std::string::npos);
    const std::string maxmip = glslInterface(findTechnique("maxmip"));
    EXPECT_NE(maxmip.find("const int kAscentAncestor = 2;"), std::string::npos) << maxmip;
    EXPECT_EQ(maxmip.find("kFarStep"), std::string::npos);
    EXPECT_EQ(glslInterface().find("kConeStall"), std::string::npos);
}

TEST(GlShaders, EveryTechniqueProgramCompiles) {
    RELIEF_REQUIRE_GL();
    auto context = *EglContext::shared();
    EglContext::Scope scope(*context);
    // Techniques with maps compile against the map declarations of real maps (a small surface).
    const auto surface = testing::generatedSurface("peaks6", 12, 10, 0.15f, EdgeMode::Clamp, 1);
    for (const TechniqueInfo& info : techniques()) {
        if (info.glsl.empty()) continue;
        std::optional<TechniqueMaps> maps;
        if (info.buildMaps) {
            auto params = resolveParams(info, {});
            ASSERT_TRUE(params) << params.error().message;
            auto built = info.buildMaps(TechniqueInput{surface, *params});
            ASSERT_TRUE(built) << info.name << ": " << built.error().message;
            maps = std::move(*built);
        }
        for (std::string_view entry : {"main_rays.glsl", "main_camera.glsl"}) {
            auto program = computeProgram(info.name,
                                          {"common_types.glsl", "common_surface.glsl",
                                           "common_cell_intersect.glsl", "common_camera.glsl",
                                           info.glsl, entry},
                                          &info, maps ? &*maps : nullptr);
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
