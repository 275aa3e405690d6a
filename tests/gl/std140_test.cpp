// The std140/std430 layouts defined once in C++ (shader_interface.h) against the GL driver: the
// generated GLSL is compiled and the driver's offsets, block sizes and array strides must be the
// C++ offsetof values, field by field.
#include <support/gl_test_support.h>

#include <relief/gl/program.h>
#include <relief/gl/shader_interface.h>

namespace relief::gl {
namespace {

// An expression reading the first scalar of a field, so that every member is used.
std::string firstScalar(const GlslField& f, const std::string& prefix) {
    std::string expr = prefix + std::string(f.name) + std::string(f.array.empty() ? "" : "[0]");
    if (f.type == "mat4") expr += "[0][0]";
    else if (f.type.find("vec") != std::string_view::npos) expr += ".x";
    return "float(" + expr + ")";
}

template <class Block>
std::string touchAll(const std::string& prefix) {
    std::string sum;
    for (const GlslField& f : BlockLayout<Block>::kFields)
        sum += (sum.empty() ? "" : " + ") + firstScalar(f, prefix);
    return sum;
}

GLint resourceProperty(GLuint program, GLenum interface, const std::string& name, GLenum property) {
    const GLuint index = glGetProgramResourceIndex(program, interface, name.c_str());
    EXPECT_NE(index, GL_INVALID_INDEX) << "GL has no resource " << name;
    if (index == GL_INVALID_INDEX) return -1;
    GLint value = -1;
    glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
    return value;
}

// Members of a block with an instance name are "Block.member"; of one without, "array[0].member".
template <class Block>
void expectSameOffsets(GLuint program, GLenum interface, const std::string& prefix) {
    for (const GlslField& f : BlockLayout<Block>::kFields) {
        const std::string name =
            prefix + std::string(f.name) + std::string(f.array.empty() ? "" : "[0]");
        EXPECT_EQ(resourceProperty(program, interface, name, GL_OFFSET), GLint(f.offset))
            << BlockLayout<Block>::kName << "::" << f.name;
    }
}

template <class Block>
void expectUniformBlockSize(GLuint program) {
    const std::string name(BlockLayout<Block>::kName);
    EXPECT_EQ(resourceProperty(program, GL_UNIFORM_BLOCK, name, GL_BUFFER_DATA_SIZE),
              GLint(sizeof(Block)))
        << name;
}

TEST(GlLayout, CppOffsetsFollowStd140) {
    // The static_asserts in RELIEF_GL_BLOCK already hold; this shows the checker can fail.
    const GlslField misplaced[] = {{"float", "a", "", 0, 4, 4}, {"vec3", "b", "", 4, 12, 16}};
    EXPECT_FALSE(followsStd140(misplaced, 32));
    const GlslField placed[] = {{"float", "a", "", 0, 4, 4}, {"vec3", "b", "", 16, 12, 16}};
    EXPECT_TRUE(followsStd140(placed, 32));
    EXPECT_FALSE(followsStd140(placed, 28));
}

TEST(GlLayout, GeneratedGlslDeclaresEveryField) {
    const std::string text = glslInterface();
    EXPECT_NE(text.find("layout(std140, binding = kSurfaceBinding) uniform SurfaceUniforms {"),
              std::string::npos)
        << text;
    for (const GlslField& f : BlockLayout<CameraUniforms>::kFields)
        EXPECT_NE(text.find(fmt::format("    {} {}{};", f.type, f.name, f.array)),
                  std::string::npos)
            << f.name;
    EXPECT_NE(text.find("vec4 params[4];"), std::string::npos);
    EXPECT_NE(text.find("const int kEdgeRepeat = 1;"), std::string::npos);
    EXPECT_EQ(glslParamName("max-steps"), "kParamMaxSteps");
    EXPECT_EQ(glslParamName("binary-steps"), "kParamBinarySteps");
}

TEST(GlLayout, DriverOffsetsMatchCpp) {
    RELIEF_REQUIRE_GL();
    auto context = *EglContext::shared();
    EglContext::Scope scope(*context);
    const std::string text = fmt::format(
        "layout(local_size_x = 1) in;\n"
        "layout(std430, binding = 0) buffer Rays {{ RayRecord rays[]; }};\n"
        "layout(std430, binding = 1) buffer Hits {{ HitRecord hits[]; }};\n"
        "void main() {{\n"
        "    hits[0].t = {} + {} + {} + {} + {} + {};\n"
        "}}\n",
        touchAll<SurfaceUniforms>("surfaceUniforms."), touchAll<TraceUniforms>("traceUniforms."),
        touchAll<CameraUniforms>("camera."), touchAll<MeshUniforms>("mesh."),
        touchAll<RayRecord>("rays[0]."), touchAll<HitRecord>("hits[1]."));
    auto program = computeProgramFromText("layout probe", text);
    ASSERT_TRUE(program) << program.error().message;
    const GLuint id = program->id();

    expectSameOffsets<SurfaceUniforms>(id, GL_UNIFORM, "SurfaceUniforms.");
    expectSameOffsets<TraceUniforms>(id, GL_UNIFORM, "TraceUniforms.");
    expectSameOffsets<CameraUniforms>(id, GL_UNIFORM, "CameraUniforms.");
    expectSameOffsets<MeshUniforms>(id, GL_UNIFORM, "MeshUniforms.");
    expectUniformBlockSize<SurfaceUniforms>(id);
    expectUniformBlockSize<TraceUniforms>(id);
    expectUniformBlockSize<CameraUniforms>(id);
    expectUniformBlockSize<MeshUniforms>(id);
    EXPECT_EQ(resourceProperty(id, GL_UNIFORM, "TraceUniforms.params[0]", GL_ARRAY_STRIDE), 16);

    expectSameOffsets<RayRecord>(id, GL_BUFFER_VARIABLE, "rays[0].");
    expectSameOffsets<HitRecord>(id, GL_BUFFER_VARIABLE, "hits[0].");
    EXPECT_EQ(resourceProperty(id, GL_BUFFER_VARIABLE, "rays[0].origin",
                               GL_TOP_LEVEL_ARRAY_STRIDE),
              GLint(sizeof(RayRecord)));
    EXPECT_EQ(resourceProperty(id, GL_BUFFER_VARIABLE, "hits[0].t",
                               GL_TOP_LEVEL_ARRAY_STRIDE),
              GLint(sizeof(HitRecord)));
    EXPECT_EQ(takeGlError(), "");
}

// Values written from C++ come out of the shader field by field (the layouts carry data).
TEST(GlLayout, UniformValuesRoundTrip) {
    RELIEF_REQUIRE_GL();
    auto context = *EglContext::shared();
    EglContext::Scope scope(*context);
    auto program = computeProgramFromText(
        "round trip",
        "layout(local_size_x = 1) in;\n"
        "layout(std430, binding = 1) buffer Out { float values[]; };\n"
        "void main() {\n"
        "    values[0] = camera.eye.z; values[1] = camera.tanHalfFovY;\n"
        "    values[2] = camera.right.y; values[3] = camera.aspect;\n"
        "    values[4] = camera.up.x; values[5] = float(camera.width);\n"
        "    values[6] = camera.forward.z; values[7] = float(camera.height);\n"
        "    values[8] = traceUniforms.params[2].w; values[9] = float(traceUniforms.rayCount);\n"
        "}\n");
    ASSERT_TRUE(program) << program.error().message;
    CameraUniforms camera;
    camera.eye = vec3(1, 2, 3);
    camera.tanHalfFovY = 4;
    camera.right = vec3(5, 6, 7);
    camera.aspect = 8;
    camera.up = vec3(9, 10, 11);
    camera.width = 12;
    camera.forward = vec3(13, 14, 15);
    camera.height = 16;
    TraceUniforms trace;
    trace.rayCount = 17;
    trace.params[2][3] = 18;  // parameter index 11
    GlBuffer cameraBuffer, traceBuffer, out;
    uploadBlock(cameraBuffer, camera);
    uploadBlock(traceBuffer, trace);
    out.ensure(10 * sizeof(float));
    glBindBufferBase(GL_UNIFORM_BUFFER, kCameraBinding, cameraBuffer.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, kTraceBinding, traceBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glUseProgram(program->id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    float values[10] = {};
    out.download(values, sizeof(values));
    const float expected[10] = {3, 4, 6, 8, 9, 12, 15, 16, 18, 17};
    for (int k = 0; k < 10; ++k) EXPECT_EQ(values[k], expected[k]) << k;
    EXPECT_EQ(takeGlError(), "");
}

}  // namespace
}  // namespace relief::gl
