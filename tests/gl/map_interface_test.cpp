// The generic map binding (shader_interface.h): GLSL names of map arrays, their buffer order, the
// generated declarations, and baked maps given to the GL backend (input.maps) or refused.
#include <support/gl_test_support.h>

#include <relief/gl/gl_tracer.h>
#include <relief/gl/shader_interface.h>
#include <relief/techniques/registry.h>

namespace relief::gl {
namespace {

TEST(GlMaps, NamesAndNaturalOrder) {
    EXPECT_EQ(glslMapName("level0"), "Level0");
    EXPECT_EQ(glslMapName("ccx+"), "CcxPlus");
    EXPECT_EQ(glslMapName("ccy-"), "CcyMinus");
    EXPECT_EQ(glslMapName("cones"), "Cones");
    TechniqueMaps maps;
    for (const char* name : {"oriented1", "level10", "level2", "level0", "level1"})
        maps.arrays.push_back({name, 1, 1, 1, {0.0f}});
    std::string order;
    for (const MapArray* a : mapOrder(maps)) order += a->name + " ";
    EXPECT_EQ(order, "level0 level1 level2 level10 oriented1 ");
}

TEST(GlMaps, DeclarationsComeFromTheArrays) {
    TechniqueMaps maps;
    maps.parameters = {{"cone-max", "12.5"}, {"variant", "0"}, {"note", "text"}};
    maps.arrays.push_back({"cones", 3, 2, 2, std::vector<float>(12)});
    maps.arrays.push_back({"ccx+", 2, 2, 3, std::vector<float>(12)});
    const std::string text = glslMapInterface(&maps);
    for (const char* expected :
         {"const int kMapCount = 2;", "const int kMapCcxPlus = 0;", "const int kMapCones = 1;",
          "#define RELIEF_MAP_CONES 1", "kMapOffset[kMapCount] = uint[](0u, 12u);",
          "kMapWidth[kMapCount] = int[](2, 3);", "kMapChannels[kMapCount] = int[](3, 2);",
          "const float kMapParamConeMax = 12.5", "const float kMapParamVariant = 0",
          "float mapTexel(int map, int x, int y, int channel)"})
        EXPECT_NE(text.find(expected), std::string::npos) << expected << "\n" << text;
    EXPECT_EQ(text.find("kMapParamNote"), std::string::npos);
    EXPECT_EQ(packMaps(maps).size(), 24u);
    EXPECT_NE(glslMapInterface(nullptr).find("const int kMapCount = 0;"), std::string::npos);
}

TEST(GlMaps, BakedMapsAreUsedOrRefused) {
    RELIEF_REQUIRE_GL();
    const TechniqueInfo& info = *findTechnique("quadtree");
    auto params = resolveParams(info, {});
    ASSERT_TRUE(params);
    const auto small = testing::generatedSurface("peaks6", 16, 12, 0.15f, EdgeMode::Clamp, 2);
    const auto other = testing::generatedSurface("peaks6", 20, 12, 0.15f, EdgeMode::Clamp, 2);
    auto maps = info.buildMaps(TechniqueInput{small, *params});
    ASSERT_TRUE(maps) << maps.error().message;
    TechniqueInput input{small, *params, &*maps};
    auto tracer = createGlTracer(info, input);
    ASSERT_TRUE(tracer) << tracer.error().message;
    const Ray ray{vec3(3.0f, 5.0f, 20.0f), glm::normalize(vec3(0.6f, 0.1f, -1.0f)), kInfinity};
    Hit gl, cpu;
    (*tracer)->traceBatch({&ray, 1}, {&gl, 1});
    auto reference = createTracer("exact", small);
    ASSERT_TRUE(reference);
    (*reference)->traceBatch({&ray, 1}, {&cpu, 1});
    EXPECT_TRUE(cpu.hit);
    EXPECT_EQ(gl.hit, cpu.hit);
    EXPECT_NEAR(gl.t, cpu.t, 1e-3f);

    // Maps of another surface: the row's check refuses them, naming the array.
    auto refused = createGlTracer(info, TechniqueInput{other, *params, &*maps});
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().kind, ErrorKind::InvalidInput);
    EXPECT_NE(refused.error().message.find("level0"), std::string::npos)
        << refused.error().message;
}

// Every GLSL row with maps checks baked ones as its create does (TechniqueInfo::check): its own
// maps are taken, those of a surface of another size are refused as invalid input.
TEST(GlMaps, EveryRowChecksBakedMaps) {
    RELIEF_REQUIRE_GL();
    const auto small = testing::generatedSurface("peaks6", 16, 12, 0.15f, EdgeMode::Clamp, 2);
    const auto other = testing::generatedSurface("peaks6", 20, 12, 0.15f, EdgeMode::Clamp, 2);
    for (const TechniqueInfo& info : techniques()) {
        if (info.glsl.empty() || !info.buildMaps) continue;
        SCOPED_TRACE(std::string(info.name));
        EXPECT_NE(info.check, nullptr);
        auto params = resolveParams(info, {});
        ASSERT_TRUE(params);
        auto maps = info.buildMaps(TechniqueInput{small, *params});
        ASSERT_TRUE(maps) << maps.error().message;
        auto taken = createGlTracer(info, TechniqueInput{small, *params, &*maps});
        EXPECT_TRUE(taken) << taken.error().message;
        auto refused = createGlTracer(info, TechniqueInput{other, *params, &*maps});
        ASSERT_FALSE(refused);
        EXPECT_EQ(refused.error().kind, ErrorKind::InvalidInput) << refused.error().message;
        auto cpu = info.create(TechniqueInput{other, *params, &*maps});
        ASSERT_FALSE(cpu);
        EXPECT_EQ(cpu.error().message, refused.error().message);
    }
}

}  // namespace
}  // namespace relief::gl
