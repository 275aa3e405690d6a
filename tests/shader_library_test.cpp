// The engine shader library (shaders/relief/, docs/engine.md), per registry row that declares a
// function: the row names a file, function and samplers that exist; the constants its C++ side
// defines (the row's glslConstants) have the same values in the library; and a fragment shader
// calling the function and its shadow query compiles as GLSL 3.30 core, GLSL ES 3.00 and Vulkan
// GLSL 4.50, whose SPIR-V spirv-cross turns into HLSL (tests/shaders/check_shader_library.py
// writes the shader and runs glslangValidator and spirv-cross).
#include <gtest/gtest.h>
#include <relief/core/generators.h>
#include <relief/techniques/registry.h>
#include <support/cli_case.h>
#include <support/shader_rows.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

namespace relief {
namespace {

const std::filesystem::path kLibrary = std::filesystem::path(RELIEF_SOURCE_DIR) / "shaders/relief";

TEST(ShaderLibraryRows, TheRowsTheIssueNamesHaveAFunction) {
    for (std::string_view name :
         {"linear", "parallax", "cone", "relaxed-cone", "maxmip", "quadtree", "qdm", "safety-cc",
          "safety-sd", "quadtree-oriented"}) {
        const TechniqueInfo* info = findTechnique(name);
        ASSERT_TRUE(info) << name;
        EXPECT_FALSE(info->shaderFunction.empty()) << name;
    }
}

class ShaderLibrary : public ::testing::TestWithParam<const TechniqueInfo*> {};

TEST_P(ShaderLibrary, RowMatchesTheLibrary) {
    const TechniqueInfo& info = *GetParam();
    const std::string text = testing::readFile(kLibrary / info.shaderFile);
    ASSERT_FALSE(text.empty()) << kLibrary / info.shaderFile;
    // Everything it includes: common.glsl and the files on its `// requires:` lines.
    std::string included = testing::readFile(kLibrary / "common.glsl");
    ASSERT_FALSE(included.empty());
    const std::regex requireLine("^// requires: (\\S+)$", std::regex::multiline);
    for (std::sregex_iterator it(text.begin(), text.end(), requireLine), end; it != end; ++it)
        included += testing::readFile(kLibrary / (*it)[1].str());
    ASSERT_FALSE(info.shaderSamplers.empty()) << info.name;
    // The signatures of docs/engine.md, line breaks anywhere between parameters.
    std::string samplers;
    for (const ShaderSampler& s : info.shaderSamplers)
        samplers += "sampler2D " + std::string(s.name) + ",\\s+";
    const std::string function(info.shaderFunction);
    const std::regex trace("ReliefHit " + function + "\\(" + samplers +
                           "vec2 uv,\\s+vec3 viewDirTangent,\\s+ReliefParams p\\)");
    EXPECT_TRUE(std::regex_search(text, trace)) << info.shaderFile << " lacks " << function;
    const std::regex shadow("float " + function + "Shadow\\(" + samplers +
                            "ReliefHit hit,\\s+vec3 lightDirTangent,\\s+ReliefParams p\\)");
    EXPECT_TRUE(std::regex_search(text, shadow))
        << info.shaderFile << " lacks " << function << "Shadow";
    // Each sampler holds the heightfield or one array the row bakes, of at most 4 channels.
    auto hf = generateHeightfield("fbm", 16, 16, 1);
    ASSERT_TRUE(hf) << hf.error().message;
    auto surface = std::make_shared<const Surface>(
        std::make_shared<const Heightfield>(std::move(*hf)), 2.0f, EdgeMode::Clamp);
    auto params = resolveParams(info, {});
    ASSERT_TRUE(params) << params.error().message;
    TechniqueMaps maps;
    if (info.buildMaps) {
        auto built = info.buildMaps(TechniqueInput{surface, *params});
        ASSERT_TRUE(built) << built.error().message;
        maps = std::move(*built);
    }
    for (const ShaderSampler& s : info.shaderSamplers) {
        if (s.array.empty()) continue;
        const MapArray* array = maps.find(std::string(s.array));
        if (!array && !s.fallback.empty()) array = maps.find(std::string(s.fallback));
        ASSERT_TRUE(array) << info.name << ": sampler " << s.name << " names no baked array "
                           << s.array;
        EXPECT_LE(array->channels, 4) << s.array;
    }
    for (const GlslConstant& c : info.glslConstants) {
        std::smatch m;
        const std::regex declaration("const (float|int) " + std::string(c.name) +
                                     " = ([-0-9.e]+);");
        const bool found =
            std::regex_search(text, m, declaration) || std::regex_search(included, m, declaration);
        ASSERT_TRUE(found) << info.name << ": the library does not declare " << c.name;
        EXPECT_EQ(m[1].str() == "int", c.integer) << c.name;
        EXPECT_EQ(float(std::stod(m[2].str())), float(c.value)) << c.name;
    }
}

// Runs check_shader_library.py with `arguments`; its output on failure.
void expectCompiles(const std::string& label, const std::string& arguments) {
    // A folder of its own (mkdtemp): two runs of the suite at once must not share it.
    std::string pattern = (std::filesystem::temp_directory_path() /
                           ("relief-shader-library-" + testing::identifierFrom(label) + "-XXXXXX"))
                              .string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr) << "mkdtemp " << pattern;
    const std::filesystem::path tmp = pattern;
    const std::filesystem::path log = tmp / "log.txt";
    const std::string command = fmt::format(
        "/usr/bin/python3 {}/tests/shaders/check_shader_library.py --library {} {} "
        "--out {} >{} 2>&1",
        RELIEF_SOURCE_DIR, kLibrary.string(), arguments, tmp.string(), log.string());
    const int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << label << ":\n"
                                                               << testing::readFile(log);
    std::filesystem::remove_all(tmp);
}

TEST_P(ShaderLibrary, CompilesForEveryTarget) {
    const TechniqueInfo& info = *GetParam();
    std::string samplers;
    for (const ShaderSampler& s : info.shaderSamplers)
        samplers += (samplers.empty() ? "" : ",") + std::string(s.name);
    for (const char* target : {"330", "300es", "vulkan"})
        expectCompiles(fmt::format("{} {}", info.name, target),
                       fmt::format("--file {} --function {} --samplers {} --target {}",
                                   info.shaderFile, info.shaderFunction, samplers, target));
}

// docs/engine.md's minimal GLSL ES 3.00 shader, with the library pasted where it says.
TEST(ShaderLibraryDoc, EngineExampleCompilesAsEs300) {
    expectCompiles("engine.md example",
                   fmt::format("--example {}/docs/engine.md --target 300es", RELIEF_SOURCE_DIR));
}

INSTANTIATE_TEST_SUITE_P(Registry, ShaderLibrary, ::testing::ValuesIn(testing::shaderLibraryRows()),
                         testing::rowTestName);

}  // namespace
}  // namespace relief
