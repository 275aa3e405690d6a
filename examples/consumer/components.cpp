// The optional parts of the installed package (find_package(relief COMPONENTS embree gl)): the
// Embree peer's triangulated surface agrees with `exact` on a fan of rays; `--gl` also prints the
// GL backend's context (or why there is none). Exit 0 when they agree.
#include <relief/core/generators.h>
#include <relief/embree/embree_scene.h>
#include <relief/gl/gl_tracer.h>
#include <relief/techniques/registry.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string_view>
#include <vector>

int main(int argc, char** argv) {
    auto heightfield = relief::generateHeightfield("peaks6", 48, 48, 1);
    if (!heightfield) return 1;
    auto surface = std::make_shared<const relief::Surface>(
        std::make_shared<const relief::Heightfield>(std::move(*heightfield)), 6.0f,
        relief::EdgeMode::Clamp);
    auto scene = relief::EmbreeScene::create(*surface);
    auto reference = relief::createTracer(relief::referenceTechnique().name, surface);
    if (!scene || !reference) return 1;

    std::vector<relief::Ray> rays(64);
    for (size_t k = 0; k < rays.size(); ++k) {
        const float angle = 0.3f * float(k);
        rays[k].origin = relief::vec3(24.0f, 24.0f, surface->maxZ() + 10.0f);
        rays[k].direction = glm::normalize(relief::vec3(std::cos(angle), std::sin(angle), -1.0f));
    }
    std::vector<relief::Hit> hits(rays.size()), expected(rays.size());
    (*scene)->intersect1(rays, hits);
    relief::traceAll(**reference, rays, expected);
    for (size_t k = 0; k < rays.size(); ++k)
        if (hits[k].hit != expected[k].hit || std::abs(hits[k].t - expected[k].t) > 1e-3f) {
            std::fprintf(stderr, "relief_consumer_components: ray %zu: embree t=%g, exact t=%g\n",
                         k, hits[k].t, expected[k].t);
            return 1;
        }
    std::printf("relief_consumer_components: embree agrees with exact on %zu rays\n", rays.size());
    if (argc > 1 && std::string_view(argv[1]) == "--gl") {
        auto gl = relief::glBackendDescription();
        std::printf("gl: %s\n", gl ? gl->c_str() : gl.error().message.c_str());
    }
    return 0;
}
