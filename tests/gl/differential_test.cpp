// CPU vs GLSL, per technique (STYLE: "a differential test per technique"): a fixed ray set on two
// maps and both edge modes is traced by the C++ tracer (createTracer) and by its GLSL twin
// (createGlTracer); every registry row with a `glsl` is tested, none is listed by hand.
//
// Contracts (DESIGN §3), and what the two sides may differ by:
// - exact: same hit/miss and |Δt| ≤ 1e-3, except float-edge rays (a ray grazing a cell edge or a
//   plane, where GPU and CPU rounding decide differently: at most 0.1%, printed).
// - conservative: as exact (the GLSL is the same arithmetic), and never past the first hit: where
//   the reference (`exact`) hits, the GL hit is at t ≤ t_ref + 1e-4 (at most 0.1% float-edge
//   rays otherwise, printed).
// - approximate: hit rates within 1 point and mean |Δt| over rays both sides hit ≤ 0.01 texel
//   (the GLSL is the same arithmetic; only a bilinear test that rounds the other way can move a
//   linear step or a bisection).
// - all: steps and fetches equal for at least 99% of rays.
// Techniques with maps build them once per scene (info.buildMaps) and both sides trace with them,
// which also checks that `create` accepts its own maps.
#include <support/gl_test_support.h>

#include <relief/gl/gl_tracer.h>
#include <relief/techniques/registry.h>

#include <cmath>
#include <random>

namespace relief {
namespace {

// Rays from outside the box aimed inside it, rays from just above S in any direction, and
// axis-parallel or vertical rays on cell edges (fixed seed).
std::vector<Ray> differentialRays(const Surface& s, uint32_t seed) {
    std::mt19937 rng(seed);
    auto uniform = [&](float lo, float hi) {
        return std::uniform_real_distribution<float>(lo, hi)(rng);
    };
    const vec3 size(float(s.width()), float(s.height()), s.depth());
    const vec3 centre = 0.5f * size;
    const float radius = 1.5f * glm::length(size);
    std::vector<Ray> rays;
    for (int k = 0; k < 1200; ++k) {
        const float el = glm::radians(uniform(-5.0f, 89.0f)), az = uniform(0.0f, 6.2832f);
        const vec3 o = centre + radius * vec3(std::cos(el) * std::cos(az),
                                              std::cos(el) * std::sin(az), std::sin(el));
        const vec3 target(uniform(0, size.x), uniform(0, size.y), uniform(0, size.z));
        rays.push_back(Ray{o, glm::normalize(target - o), kInfinity});
    }
    for (int k = 0; k < 400; ++k) {
        const float x = uniform(0, size.x), y = uniform(0, size.y);
        const float z = s.heightAt(x, y) + 0.01f + uniform(0.0f, 0.5f * size.z);
        vec3 d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        if (glm::length(d) < 1e-3f) d = vec3(0, 0, -1);
        rays.push_back(Ray{vec3(x, y, z), glm::normalize(d), kInfinity});
    }
    const float top = s.maxZ() + 0.5f;
    for (int k = 0; k < 200; ++k) {
        const float edgeX = std::floor(uniform(0, size.x)) + 0.5f;
        const float edgeY = std::floor(uniform(0, size.y)) + 0.5f;
        switch (k % 3) {
            case 0:
                rays.push_back(Ray{vec3(-1.0f, edgeY, top),
                                   glm::normalize(vec3(1, 0, -uniform(0.02f, 0.3f))), kInfinity});
                break;
            case 1:
                rays.push_back(Ray{vec3(edgeX, -1.0f, top),
                                   glm::normalize(vec3(0, 1, -uniform(0.02f, 0.3f))), kInfinity});
                break;
            default:
                rays.push_back(Ray{vec3(edgeX + 0.25f, edgeY, top), vec3(0, 0, -1), kInfinity});
                break;
        }
    }
    return rays;
}

struct Scene {
    std::string name;
    std::shared_ptr<const Surface> surface;
};

std::vector<Scene> scenes() {
    std::vector<Scene> all;
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const std::string mode(toString(edge));
        all.push_back({"peaks6 64x48 " + mode,
                       testing::generatedSurface("peaks6", 64, 48, 0.15f, edge, 7)});
        all.push_back({"walls 40x40 " + mode,
                       testing::generatedSurface("walls", 40, 40, 0.15f, edge, 3)});
    }
    return all;
}

std::vector<const TechniqueInfo*> glTechniques() {
    std::vector<const TechniqueInfo*> list;
    for (const TechniqueInfo& info : techniques())
        if (!info.glsl.empty()) list.push_back(&info);
    return list;
}

// `rays` traced by the row's C++ tracer into `cpu` and by its GLSL twin into `gl`, both with the
// maps built once here (which also checks that `create` accepts its own maps).
void traceBothSides(const TechniqueInfo& info, std::shared_ptr<const Surface> surface,
                    const ParamValues& params, const std::vector<Ray>& rays,
                    std::vector<Hit>& cpu, std::vector<Hit>& gl) {
    TechniqueInput input{std::move(surface), params};
    TechniqueMaps maps;
    if (info.buildMaps) {
        auto built = info.buildMaps(input);
        ASSERT_TRUE(built) << built.error().message;
        maps = std::move(*built);
        input.maps = &maps;
    }
    auto cpuTracer = info.create(input);
    ASSERT_TRUE(cpuTracer) << cpuTracer.error().message;
    auto glTracer = createGlTracer(info, input);
    ASSERT_TRUE(glTracer) << glTracer.error().message;
    cpu.assign(rays.size(), Hit{});
    gl.assign(rays.size(), Hit{});
    traceAll(**cpuTracer, rays, cpu);
    (*glTracer)->traceBatch(rays, gl);
}

class CpuVsGl : public ::testing::TestWithParam<const TechniqueInfo*> {};

TEST_P(CpuVsGl, AgreeOnFixedRays) {
    RELIEF_REQUIRE_GL();
    const TechniqueInfo& info = *GetParam();
    auto params = resolveParams(info, {});
    ASSERT_TRUE(params) << params.error().message;

    size_t total = 0, hitMismatch = 0, tMismatch = 0, stepsDiffer = 0, fetchesDiffer = 0;
    size_t cpuHits = 0, glHits = 0, bothHit = 0, pastFirstHit = 0;
    double sumAbsDt = 0.0, maxAbsDt = 0.0;
    const bool checkFirstHit = info.contract == Contract::Conservative;
    for (const Scene& scene : scenes()) {
        ASSERT_TRUE(scene.surface);
        const std::vector<Ray> rays = differentialRays(*scene.surface, 11);
        std::vector<Hit> cpuHit, glHit, refHit;
        ASSERT_NO_FATAL_FAILURE(traceBothSides(info, scene.surface, *params, rays, cpuHit, glHit));
        if (checkFirstHit) {
            auto reference = createTracer("exact", scene.surface);
            ASSERT_TRUE(reference) << reference.error().message;
            refHit.resize(rays.size());
            traceAll(**reference, rays, refHit);
        }
        for (size_t k = 0; k < rays.size(); ++k) {
            const Hit& a = cpuHit[k];
            const Hit& b = glHit[k];
            ++total;
            if (checkFirstHit && refHit[k].hit && (!b.hit || b.t > refHit[k].t + 1e-4f)) {
                ++pastFirstHit;
                const Ray& r = rays[k];
                std::printf("  %s [%s] ray %zu o=(%.9g, %.9g, %.9g) d=(%.9g, %.9g, %.9g): "
                            "past the first hit: reference t=%.7g, gl %s t=%.7g\n",
                            info.name.data(), scene.name.c_str(), k, r.origin.x, r.origin.y,
                            r.origin.z, r.direction.x, r.direction.y, r.direction.z,
                            refHit[k].t, b.hit ? "hit" : "miss", b.t);
            }
            cpuHits += a.hit;
            glHits += b.hit;
            stepsDiffer += a.steps != b.steps;
            fetchesDiffer += a.fetches != b.fetches;
            const double dt = a.hit && b.hit ? std::abs(double(a.t) - double(b.t)) : 0.0;
            if (a.hit && b.hit) {
                ++bothHit;
                sumAbsDt += dt;
                maxAbsDt = std::max(maxAbsDt, dt);
            }
            const bool hitDiffers = a.hit != b.hit, tDiffers = dt > 1e-3;
            hitMismatch += hitDiffers;
            tMismatch += tDiffers;
            // Every exact disagreement is printed; for the others, the first few.
            const bool print = info.contract != Contract::Approximate ||
                               hitMismatch + tMismatch <= 10;
            if (print && (hitDiffers || tDiffers)) {
                const Ray& r = rays[k];
                std::printf("  %s [%s] ray %zu o=(%.9g, %.9g, %.9g) d=(%.9g, %.9g, %.9g): "
                            "cpu %s t=%.7g steps=%d, gl %s t=%.7g steps=%d\n",
                            info.name.data(), scene.name.c_str(), k, r.origin.x, r.origin.y,
                            r.origin.z, r.direction.x, r.direction.y, r.direction.z,
                            a.hit ? "hit" : "miss", a.t, a.steps, b.hit ? "hit" : "miss", b.t,
                            b.steps);
            }
        }
    }
    const double meanAbsDt = bothHit ? sumAbsDt / double(bothHit) : 0.0;
    std::printf("%s (%s): %zu rays, cpu hits %zu, gl hits %zu, hit/miss differ %zu, "
                "|dt|>1e-3 %zu, mean |dt| %.3g, max |dt| %.3g, steps differ %zu, "
                "fetches differ %zu\n",
                info.name.data(), toString(info.contract).data(), total, cpuHits, glHits,
                hitMismatch, tMismatch, meanAbsDt, maxAbsDt, stepsDiffer, fetchesDiffer);

    if (checkFirstHit) std::printf("%s: past the first hit %zu\n", info.name.data(), pastFirstHit);

    ASSERT_GT(total, 0u);
    if (info.contract != Contract::Approximate) {
        EXPECT_LE(double(hitMismatch + tMismatch), 1e-3 * double(total));
        EXPECT_LE(double(pastFirstHit), 1e-3 * double(total));
    } else {
        EXPECT_LE(std::abs(double(cpuHits) - double(glHits)), 0.01 * double(total));
        EXPECT_LE(meanAbsDt, 0.01);
    }
    EXPECT_LE(double(stepsDiffer), 0.01 * double(total));
    EXPECT_LE(double(fetchesDiffer), 0.01 * double(total));
}

// Parameters that change the GLSL's path (each GLSL row's pathCases: encodings, policies,
// variants), on one small scene with maps built once: the two sides must agree bit for bit up to
// float-edge rays, as above. Repeat mode, or clamp for the cases that need it (exterior rays).
TEST(CpuVsGlParameters, AgreeOnFixedRays) {
    RELIEF_REQUIRE_GL();
    size_t cases = 0;
    for (const TechniqueInfo& info : techniques()) {
        if (info.glsl.empty()) continue;
        for (const PathCase& c : info.pathCases) {
            ++cases;
            const EdgeMode edge = c.clampOnly ? EdgeMode::Clamp : EdgeMode::Repeat;
            const auto surface = testing::generatedSurface("peaks6", 40, 32, 0.15f, edge, 5);
            ASSERT_TRUE(surface);
            const std::vector<Ray> rays = differentialRays(*surface, 23);
            const std::string label = fmt::format("{} {}", info.name, c.params);
            auto overrides = parseParamList(c.params);
            ASSERT_TRUE(overrides) << overrides.error().message;
            auto params = resolveParams(info, *overrides);
            ASSERT_TRUE(params) << params.error().message;
            std::vector<Hit> a, b;
            ASSERT_NO_FATAL_FAILURE(traceBothSides(info, surface, *params, rays, a, b)) << label;
            size_t differ = 0, stepsDiffer = 0;
            for (size_t k = 0; k < rays.size(); ++k) {
                differ += a[k].hit != b[k].hit ||
                          (a[k].hit && std::abs(double(a[k].t) - double(b[k].t)) > 1e-3);
                stepsDiffer += a[k].steps != b[k].steps || a[k].fetches != b[k].fetches;
            }
            std::printf("%s: %zu rays, hit or t differ %zu, steps or fetches differ %zu\n",
                        label.c_str(), rays.size(), differ, stepsDiffer);
            EXPECT_LE(double(differ), 1e-3 * double(rays.size())) << label;
            EXPECT_LE(double(stepsDiffer), 0.01 * double(rays.size())) << label;
        }
    }
    EXPECT_GT(cases, 0u);
}

INSTANTIATE_TEST_SUITE_P(Registry, CpuVsGl, ::testing::ValuesIn(glTechniques()),
                         [](const ::testing::TestParamInfo<const TechniqueInfo*>& p) {
                             std::string name;
                             for (char c : p.param->name)
                                 name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                             return name;
                         });

}  // namespace
}  // namespace relief
