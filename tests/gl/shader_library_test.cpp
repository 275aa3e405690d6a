// The engine shader library (shaders/relief/) against the CPU tracers, per registry row that
// declares a shader function: a quad is drawn with a real vertex + fragment shader (GLSL 3.30
// core on llvmpipe) whose fragment shader calls the row's function on float textures holding
// the bake's arrays, and writes its hit (texel position, uv, depth, steps), its shadow query and
// the exact uv and tangent-space view direction it passed. The CPU builds the same texel-space
// rays from those values (viewRay: the library's reliefViewRay in C++) and traces them with the
// row's CPU tracer (the same maps) and with the reference.
//
// Views: the quad in the xy plane seen from four elevations and azimuths, and a tilted quad
// (another tangent frame, mesh at mid-level 0.5); clamp and repeat scenes; the row's path cases.
// Contracts (contractOf):
// - exact / conservative: no miss and no overshoot: where the reference hits, the GPU hits at
//   t <= t_ref + kFloatSlack; the GPU and the CPU tracer agree on hit/miss and within
//   kFloatSlack on t. kFloatSlack = 2e-3 texel: 1e-3 (DESIGN §3) plus what float32 rounding
//   apart from the CPU's arithmetic (no `precise`, no fp64 division) moves a hit at these
//   depths; rays whose two sides round to different cells (a hit/miss flip at a plane or cell
//   edge) may be at most 0.1%, each printed. Shadows (from the GPU's hit toward a light) agree
//   with the CPU tracer on the same shadow ray for 99% of hits.
// - approximate: the error against the CPU tracer and the reference is printed; bounded loosely
//   (hit rates within 1%, mean |Δt| against the CPU tracer <= 0.05 texel).
#include <relief/gl/egl_context.h>
#include <relief/gl/program.h>
#include <relief/gl/shader_library.h>
#include <relief/techniques/registry.h>
#include <support/gl_test_support.h>
#include <support/shader_rows.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace relief {
namespace {

using gl::GlFramebuffer;
using gl::GlProgram;
using gl::GlTexture;
using gl::GlVertexArray;
using gl::LibraryParams;

constexpr float kFloatSlack = 2e-3f;
constexpr int kImageSize = 72;
const vec3 kLightTangent = glm::normalize(vec3(0.5f, 0.3f, 0.6f));

// reliefTexelDirection and reliefViewRay (common.glsl) in C++.
vec3 texelDirection(vec3 t, const Surface& s) {
    return glm::normalize(
        vec3(t.x * float(s.width()), t.y * float(s.height()), t.z * float(s.width())));
}
Ray viewRay(vec2 uv, vec3 viewDir, const Surface& s, float midLevel) {
    const vec3 d = -texelDirection(viewDir, s);
    vec3 o(uv.x * float(s.width()), uv.y * float(s.height()), s.depth() * midLevel);
    if (midLevel < 1.0f && d.z < 0.0f) o -= d * ((s.depth() - o.z) / -d.z);
    return Ray{o, d, kInfinity};
}

// A view: the quad origin + u·U + v·V (world), the eye, and where it looks.
struct View {
    std::string name;
    vec3 origin, axisU, axisV, eye;
    float midLevel = 1.0f;
};

std::vector<View> views() {
    std::vector<View> all;
    const vec3 centre(0.5f, 0.5f, 0.0f);
    const float elevations[] = {88.0f, 65.0f, 40.0f, 20.0f},
                azimuths[] = {10.0f, 35.0f, 130.0f, 250.0f};
    for (int k = 0; k < 4; ++k) {
        const float el = glm::radians(elevations[k]), az = glm::radians(azimuths[k]);
        const vec3 eye = centre + 1.4f * vec3(std::cos(el) * std::cos(az),
                                              std::cos(el) * std::sin(az), std::sin(el));
        all.push_back({fmt::format("elevation {}", elevations[k]), vec3(0), vec3(1, 0, 0),
                       vec3(0, 1, 0), eye});
    }
    // Tilted: the quad turned 40° about (1, 1, 0) and 25° about z, the mesh at mid-level.
    const glm::mat3 turn =
        glm::mat3(
            glm::rotate(glm::mat4(1.0f), glm::radians(40.0f), glm::normalize(vec3(1, 1, 0)))) *
        glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(25.0f), vec3(0, 0, 1)));
    const vec3 u = turn * vec3(1, 0, 0), v = turn * vec3(0, 1, 0), n = glm::cross(u, v);
    const vec3 origin = -0.5f * (u + v);
    all.push_back(
        {"tilted quad", origin, u, v, 1.5f * glm::normalize(n + 0.6f * u - 0.3f * v), 0.5f});
    return all;
}

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec2 corner;
uniform mat4 clipFromWorld;
uniform vec3 quadOrigin, quadU, quadV;
out vec2 vUv;
out vec3 vWorld;
void main() {
    vUv = corner;
    vWorld = quadOrigin + corner.x * quadU + corner.y * quadV;
    gl_Position = clipFromWorld * vec4(vWorld, 1.0);
}
)";

// The fragment shader: the library, then a main that calls the row's function.
std::string fragmentShader(const TechniqueInfo& info) {
    std::string samplers, arguments;
    for (const ShaderSampler& s : info.shaderSamplers) {
        samplers += fmt::format("uniform sampler2D {};\n", s.name);
        arguments += std::string(s.name) + ", ";
    }
    return fmt::format(R"(#version 330 core
{}
{}uniform ReliefParams params;
uniform vec3 eye, quadU, quadV, lightTangent;
in vec2 vUv;
in vec3 vWorld;
layout(location = 0) out vec4 outHit;   // hit, texel position
layout(location = 1) out vec4 outUv;    // uv used, steps, shadow
layout(location = 2) out vec4 outView;  // view direction used, 1 = covered
layout(location = 3) out vec4 outHitUv; // hit uv, depth
void main() {{
    // Tangent space in uv units: x along U, y along V, z along the normal in U's units.
    vec3 toEye = eye - vWorld, n = normalize(cross(quadU, quadV));
    float lu = length(quadU), lv = length(quadV);
    vec3 viewDir = vec3(dot(toEye, quadU) / (lu * lu), dot(toEye, quadV) / (lv * lv),
                        dot(toEye, n) / lu);
    vec2 uv = vUv;
    ReliefHit hit = {}({}uv, viewDir, params);
    float lit = {}Shadow({}hit, lightTangent, params);
    outHit = vec4(hit.hit ? 1.0 : 0.0, hit.position);
    outUv = vec4(uv, float(hit.steps), lit);
    outView = vec4(viewDir, 1.0);
    outHitUv = vec4(hit.uv, hit.depth, 0.0);
}}
)",
                       *gl::shaderLibraryText(info.shaderFile), samplers, info.shaderFunction, arguments,
                       info.shaderFunction, arguments);
}

glm::mat4 clipFromWorld(const View& view) {
    const vec3 centre = view.origin + 0.5f * (view.axisU + view.axisV);
    const vec3 forward = glm::normalize(centre - view.eye);
    const vec3 up = std::abs(forward.z) > 0.99f ? vec3(0, 1, 0) : vec3(0, 0, 1);
    return glm::perspective(glm::radians(50.0f), 1.0f, 0.05f, 10.0f) *
           glm::lookAt(view.eye, centre, up);
}

// What one pixel gave: the fragment shader's outputs.
struct Fragment {
    vec4 hit, uv, view, hitUv;
};

// Draws the quad of `view` with the row's function; the covered pixels' outputs.
std::vector<Fragment> drawQuad(const GlProgram& program, const TechniqueInfo& info,
                               const Surface& surface, const TechniqueMaps& maps,
                               const LibraryParams& lp, const View& view) {
    auto textures = gl::libraryTextures(info, surface.heightfield(), maps);
    EXPECT_TRUE(textures) << (textures ? "" : textures.error().message);
    if (!textures) return {};
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    GlFramebuffer framebuffer(id);
    std::vector<GlTexture> targets;
    GLenum buffers[4];
    for (int k = 0; k < 4; ++k) {
        targets.push_back(gl::floatTexture(kImageSize, kImageSize, 4, nullptr));
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0 + k, targets.back().id(), 0);
        buffers[k] = GL_COLOR_ATTACHMENT0 + k;
    }
    glNamedFramebufferDrawBuffers(id, 4, buffers);
    EXPECT_EQ(glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));

    const float corners[] = {0, 0, 1, 0, 0, 1, 1, 1};
    GLuint vbo = 0;
    glCreateBuffers(1, &vbo);
    glNamedBufferData(vbo, sizeof(corners), corners, GL_STATIC_DRAW);
    glCreateVertexArrays(1, &id);
    GlVertexArray vertexArray(id);
    glVertexArrayVertexBuffer(id, 0, vbo, 0, 2 * sizeof(float));
    glVertexArrayAttribFormat(id, 0, 2, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(id, 0, 0);
    glEnableVertexArrayAttrib(id, 0);

    const GLuint p = program.id();
    glUseProgram(p);
    auto uniform = [&](const char* name) { return glGetUniformLocation(p, name); };
    glUniformMatrix4fv(uniform("clipFromWorld"), 1, GL_FALSE, &clipFromWorld(view)[0][0]);
    glUniform3fv(uniform("quadOrigin"), 1, &view.origin.x);
    glUniform3fv(uniform("quadU"), 1, &view.axisU.x);
    glUniform3fv(uniform("quadV"), 1, &view.axisV.x);
    glUniform3fv(uniform("eye"), 1, &view.eye.x);
    glUniform3fv(uniform("lightTangent"), 1, &kLightTangent.x);
    LibraryParams at = lp;
    at.midLevel = view.midLevel;
    gl::setLibraryUniforms(p, "params", surface, at);
    gl::bindLibraryTextures(p, info, *textures);

    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, kImageSize, kImageSize);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const float zero[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4; ++k) glClearBufferfv(GL_COLOR, k, zero);
    glBindVertexArray(vertexArray.id());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);

    std::vector<std::vector<vec4>> planes(4, std::vector<vec4>(size_t(kImageSize) * kImageSize));
    for (int k = 0; k < 4; ++k) {
        glNamedFramebufferReadBuffer(id = framebuffer.id(), GL_COLOR_ATTACHMENT0 + k);
        glReadPixels(0, 0, kImageSize, kImageSize, GL_RGBA, GL_FLOAT, planes[size_t(k)].data());
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteBuffers(1, &vbo);
    EXPECT_EQ(gl::takeGlError(), "");
    std::vector<Fragment> covered;
    for (size_t k = 0; k < planes[0].size(); ++k)
        if (planes[2][k].w == 1.0f)
            covered.push_back({planes[0][k], planes[1][k], planes[2][k], planes[3][k]});
    return covered;
}

struct Tally {
    size_t rays = 0, gpuHits = 0, cpuHits = 0, hitDiffers = 0, tDiffers = 0, missed = 0,
           overshot = 0;
    size_t litChecked = 0, shadowDiffers = 0;
    double sumDt = 0, maxDt = 0, sumRefDt = 0;
    size_t bothHit = 0, refBoth = 0;
};

// One scene × parameter set: every view drawn, every covered pixel checked against the CPU.
void checkScene(const TechniqueInfo& info, std::shared_ptr<const Surface> surface,
                const std::vector<std::pair<std::string, double>>& overrides,
                const std::string& label, Tally& tally) {
    auto params = resolveParams(info, overrides);
    ASSERT_TRUE(params) << params.error().message;
    const Contract contract = contractOf(info, *params);
    const bool promises = contract != Contract::Approximate;
    TechniqueInput input{surface, *params};
    MapFile file;
    file.source = mapSourceOf(*surface);
    if (info.buildMaps) {
        auto built = info.buildMaps(input);
        ASSERT_TRUE(built) << built.error().message;
        file.techniques.push_back(std::move(*built));
    }
    const TechniqueMaps empty;
    const TechniqueMaps& maps = file.techniques.empty() ? empty : file.techniques.front();
    const LibraryParams lp = gl::libraryParams(info, *params, maps);

    auto cpu =
        createTracer(info.name, surface, overrides, file.techniques.empty() ? nullptr : &file);
    ASSERT_TRUE(cpu) << cpu.error().message;
    auto reference = createTracer(referenceTechnique().name, surface);
    ASSERT_TRUE(reference) << reference.error().message;
    auto program = gl::graphicsProgramFromText(info.name, kVertexShader, fragmentShader(info));
    ASSERT_TRUE(program) << program.error().message;

    for (const View& view : views()) {
        const std::vector<Fragment> fragments = drawQuad(*program, info, *surface, maps, lp, view);
        ASSERT_GT(fragments.size(), size_t(kImageSize * kImageSize / 20))
            << label << " " << view.name;
        std::vector<Ray> rays;
        for (const Fragment& f : fragments)
            rays.push_back(viewRay(vec2(f.uv), vec3(f.view), *surface, view.midLevel));
        std::vector<Hit> cpuHits(rays.size()), refHits(rays.size());
        traceAll(**cpu, rays, cpuHits);
        traceAll(**reference, rays, refHits);
        // Shadow rays of the GPU's hits (reliefShadowRay), traced by the CPU tracer.
        std::vector<Ray> shadowRays;
        std::vector<size_t> shadowOf;
        for (size_t k = 0; k < rays.size(); ++k) {
            if (fragments[k].hit.x != 1.0f) continue;
            const vec3 o = vec3(fragments[k].hit.y, fragments[k].hit.z, fragments[k].hit.w) +
                           vec3(0, 0, 1e-3f);
            shadowRays.push_back(Ray{o, texelDirection(kLightTangent, *surface), kInfinity});
            shadowOf.push_back(k);
        }
        std::vector<Hit> shadowHits(shadowRays.size());
        traceAll(**cpu, shadowRays, shadowHits);
        // Only the rows that promise something have a CPU tracer whose shadow ray means the
        // same (the others' queries are reliefShadowMarch, an approximation of their own).
        for (size_t s = 0; promises && s < shadowRays.size(); ++s) {
            const float gpuLit = fragments[shadowOf[s]].uv.w;
            ++tally.litChecked;
            tally.shadowDiffers += (gpuLit == 1.0f) == shadowHits[s].hit;
        }
        for (size_t k = 0; k < rays.size(); ++k) {
            const Fragment& f = fragments[k];
            const bool gpuHit = f.hit.x == 1.0f;
            const vec3 position(f.hit.y, f.hit.z, f.hit.w);
            const float t = glm::dot(position - rays[k].origin, rays[k].direction);
            const Hit& c = cpuHits[k];
            const Hit& r = refHits[k];
            ++tally.rays;
            tally.gpuHits += gpuHit;
            tally.cpuHits += c.hit;
            const bool hitDiffers = gpuHit != c.hit;
            const double dt = gpuHit && c.hit ? std::abs(double(t) - double(c.t)) : 0.0;
            tally.hitDiffers += hitDiffers;
            tally.tDiffers += dt > kFloatSlack;
            if (gpuHit && c.hit) {
                ++tally.bothHit;
                tally.sumDt += dt;
                tally.maxDt = std::max(tally.maxDt, dt);
            }
            if (gpuHit && r.hit) {
                ++tally.refBoth;
                tally.sumRefDt += std::abs(double(t) - double(r.t));
            }
            const bool missed = r.hit && !gpuHit,
                       overshot = r.hit && gpuHit && t > r.t + kFloatSlack;
            if (promises) {
                tally.missed += missed;
                tally.overshot += overshot;
            }
            const bool print = promises ? (hitDiffers || dt > kFloatSlack || missed || overshot)
                                        : (hitDiffers && tally.hitDiffers <= 5);
            if (print)
                std::printf(
                    "  %s [%s, %s] uv=(%.7g, %.7g) view=(%.7g, %.7g, %.7g): gpu %s t=%.7g "
                    "steps=%g, cpu %s t=%.7g steps=%d, reference %s t=%.7g\n",
                    info.name.data(), label.c_str(), view.name.c_str(), f.uv.x, f.uv.y, f.view.x,
                    f.view.y, f.view.z, gpuHit ? "hit" : "miss", t, f.uv.z, c.hit ? "hit" : "miss",
                    c.t, c.steps, r.hit ? "hit" : "miss", r.t);
            // The hit's uv and depth are its texel position in the engine's units.
            if (gpuHit) {
                EXPECT_NEAR(f.hitUv.x * float(surface->width()), position.x, 1e-3f);
                EXPECT_NEAR(f.hitUv.y * float(surface->height()), position.y, 1e-3f);
                EXPECT_NEAR(f.hitUv.z * float(surface->width()),
                            surface->depth() * view.midLevel - position.z, 1e-3f);
            }
        }
    }
}

class ShaderLibraryVsCpu : public ::testing::TestWithParam<const TechniqueInfo*> {};

TEST_P(ShaderLibraryVsCpu, SameHitsOnQuads) {
    RELIEF_REQUIRE_GL();
    const TechniqueInfo& info = *GetParam();
    auto context = gl::EglContext::shared();
    ASSERT_TRUE(context);
    gl::EglContext::Scope scope(**context);

    struct Case {
        std::string label;
        std::shared_ptr<const Surface> surface;
        std::string params;
    };
    std::vector<Case> cases = {
        {"peaks6 64x64 clamp",
         testing::generatedSurface("peaks6", 64, 64, 0.15f, EdgeMode::Clamp, 7), ""},
        {"walls 48x48 repeat",
         testing::generatedSurface("walls", 48, 48, 0.15f, EdgeMode::Repeat, 3), ""},
    };
    for (const PathCase& c : info.pathCases)
        cases.push_back({fmt::format("fbm 40x40 clamp {}", c.params),
                         testing::generatedSurface("fbm", 40, 40, 0.15f, EdgeMode::Clamp, 5),
                         std::string(c.params)});
    Tally contractTally, approximateTally;
    for (const Case& c : cases) {
        ASSERT_TRUE(c.surface);
        auto overrides = parseParamList(c.params);
        ASSERT_TRUE(overrides) << overrides.error().message;
        auto params = resolveParams(info, *overrides);
        ASSERT_TRUE(params) << params.error().message;
        const bool promises = contractOf(info, *params) != Contract::Approximate;
        Tally& tally = promises ? contractTally : approximateTally;
        const Tally before = tally;
        ASSERT_NO_FATAL_FAILURE(checkScene(info, c.surface, *overrides, c.label, tally));
        std::printf(
            "%s [%s] (%s): %zu rays, gpu hits %zu, cpu hits %zu, hit/miss differ %zu, "
            "|dt|>%.0e %zu, mean |dt| vs cpu %.3g, max %.3g, mean |t-t_ref| %.3g, "
            "missed %zu, overshot %zu, shadows differ %zu of %zu\n",
            info.name.data(), c.label.c_str(), toString(contractOf(info, *params)).data(),
            tally.rays - before.rays, tally.gpuHits - before.gpuHits,
            tally.cpuHits - before.cpuHits, tally.hitDiffers - before.hitDiffers,
            double(kFloatSlack), tally.tDiffers - before.tDiffers,
            tally.bothHit > before.bothHit
                ? (tally.sumDt - before.sumDt) / double(tally.bothHit - before.bothHit)
                : 0.0,
            tally.maxDt,
            tally.refBoth > before.refBoth
                ? (tally.sumRefDt - before.sumRefDt) / double(tally.refBoth - before.refBoth)
                : 0.0,
            tally.missed - before.missed, tally.overshot - before.overshot,
            tally.shadowDiffers - before.shadowDiffers, tally.litChecked - before.litChecked);
    }
    if (contractTally.rays > 0) {
        const double n = double(contractTally.rays);
        EXPECT_LE(double(contractTally.missed + contractTally.overshot), 1e-3 * n);
        EXPECT_LE(double(contractTally.hitDiffers + contractTally.tDiffers), 1e-3 * n);
        EXPECT_LE(double(contractTally.shadowDiffers), 0.01 * double(contractTally.litChecked));
    }
    if (approximateTally.rays > 0) {
        const double n = double(approximateTally.rays);
        EXPECT_LE(std::abs(double(approximateTally.gpuHits) - double(approximateTally.cpuHits)),
                  0.01 * n);
        EXPECT_LE(approximateTally.bothHit
                      ? approximateTally.sumDt / double(approximateTally.bothHit)
                      : 0.0,
                  0.05);
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, ShaderLibraryVsCpu,
                         ::testing::ValuesIn(testing::shaderLibraryRows()), testing::rowTestName);

}  // namespace
}  // namespace relief
