// The EGL context: created once, describes itself, usable from several threads in turn.
#include <support/gl_test_support.h>

#include <relief/gl/gl_tracer.h>
#include <relief/gl/program.h>
#include <relief/techniques/registry.h>

#include <cstdlib>
#include <thread>

namespace relief {
namespace {

TEST(GlContext, CreatesAnOpenGL45CoreContext) {
    RELIEF_REQUIRE_GL();
    auto description = glBackendDescription();
    ASSERT_TRUE(description) << description.error().message;
    std::printf("GL backend: %s\n", description->c_str());
    auto context = *gl::EglContext::shared();
    gl::EglContext::Scope scope(*context);
    EXPECT_GE(epoxy_gl_version(), 45);
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_EQ(gl::takeGlError(), "");
}

TEST(GlContext, ScopesNestAndMoveBetweenThreads) {
    RELIEF_REQUIRE_GL();
    auto context = *gl::EglContext::shared();
    {
        gl::EglContext::Scope outer(*context);
        gl::EglContext::Scope inner(*context);
        EXPECT_NE(glGetString(GL_VERSION), nullptr);
    }
    std::thread other([&] {
        gl::EglContext::Scope scope(*context);
        EXPECT_NE(glGetString(GL_VERSION), nullptr);
    });
    other.join();
}

// traceBatch from several threads at once: serialized on the context, same answers.
TEST(GlContext, ConcurrentBatchesAgreeWithOneBatch) {
    RELIEF_REQUIRE_GL();
    auto surface = testing::generatedSurface("fbm", 32, 32, 0.15f, EdgeMode::Clamp);
    const TechniqueInfo& info = *findTechnique("exact");
    auto params = resolveParams(info, {});
    ASSERT_TRUE(params);
    auto tracer = createGlTracer(info, TechniqueInput{surface, *params});
    ASSERT_TRUE(tracer) << tracer.error().message;
    std::vector<Ray> rays;
    for (int k = 0; k < 4000; ++k) {
        const float a = 0.01f * float(k);
        rays.push_back(Ray{vec3(16.0f + 30.0f * std::cos(a), 16.0f + 30.0f * std::sin(a), 12.0f),
                           glm::normalize(vec3(-std::cos(a), -std::sin(a), -0.4f)), kInfinity});
    }
    std::vector<Hit> whole(rays.size()), parts(rays.size());
    (*tracer)->traceBatch(rays, whole);
    std::vector<std::thread> threads;
    for (size_t part = 0; part < 4; ++part)
        threads.emplace_back([&, part] {
            const size_t n = rays.size() / 4;
            (*tracer)->traceBatch(std::span(rays).subspan(part * n, n),
                                  std::span(parts).subspan(part * n, n));
        });
    for (std::thread& t : threads) t.join();
    int hits = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        ASSERT_EQ(whole[k].hit, parts[k].hit) << k;
        if (whole[k].hit) {
            EXPECT_EQ(whole[k].t, parts[k].t) << k;
        }
        hits += whole[k].hit;
    }
    EXPECT_GT(hits, 100);
}

// With every platform excluded, the error lists each one and says no display was found.
TEST(GlContext, FailureNamesEveryPlatformTried) {
    const char* old = std::getenv("RELIEF_EGL_PLATFORM");
    const std::string saved = old ? old : "";
    ::setenv("RELIEF_EGL_PLATFORM", "none", 1);
    auto context = gl::EglContext::create();
    if (old) ::setenv("RELIEF_EGL_PLATFORM", saved.c_str(), 1);
    else ::unsetenv("RELIEF_EGL_PLATFORM");
    ASSERT_FALSE(context);
    EXPECT_EQ(context.error().kind, ErrorKind::Unsupported);
    const std::string& message = context.error().message;
    for (const char* platform : {"surfaceless: skipped", "device: skipped", "default: skipped"})
        EXPECT_NE(message.find(platform), std::string::npos) << message;
}

TEST(GlContext, TechniqueWithoutGlslIsAClearError) {
    RELIEF_REQUIRE_GL();
    TechniqueInfo info = *findTechnique("parallax");
    info.glsl = {};
    auto surface = testing::generatedSurface("flat", 8, 8, 0.1f, EdgeMode::Clamp);
    auto tracer = createGlTracer(info, TechniqueInput{surface, {}});
    ASSERT_FALSE(tracer);
    EXPECT_EQ(tracer.error().kind, ErrorKind::Unsupported);
    EXPECT_NE(tracer.error().message.find("no GLSL tracer"), std::string::npos);
}

// A CPU-only variant (VariantSpec::cpuOnly: quadtree's and maxmip's texel boxes) is refused,
// not traced with the GLSL's cell walk.
TEST(GlContext, CpuOnlyVariantIsRefused) {
    RELIEF_REQUIRE_GL();
    auto surface = testing::generatedSurface("fbm", 8, 8, 0.1f, EdgeMode::Clamp);
    for (const char* name : {"quadtree", "maxmip"}) {
        const TechniqueInfo& info = *findTechnique(name);
        const auto params = resolveParams(info, {{"box-surface", 2}});
        auto tracer = createGlTracer(info, TechniqueInput{surface, *params});
        ASSERT_FALSE(tracer) << name;
        EXPECT_EQ(tracer.error().kind, ErrorKind::Unsupported) << name;
        EXPECT_NE(tracer.error().message.find("CPU only"), std::string::npos)
            << tracer.error().message;
    }
}

TEST(GlContext, BadParametersAreRefusedLikeOnTheCpu) {
    RELIEF_REQUIRE_GL();
    const TechniqueInfo& info = *findTechnique("exact");
    auto surface = testing::generatedSurface("flat", 8, 8, 0.1f, EdgeMode::Clamp);
    ParamValues params;
    params.set("max-steps", 5);
    auto tracer = createGlTracer(info, TechniqueInput{surface, params});
    ASSERT_FALSE(tracer);
    EXPECT_EQ(tracer.error().kind, ErrorKind::BadArgument);
}

}  // namespace
}  // namespace relief
