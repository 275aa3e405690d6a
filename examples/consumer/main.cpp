// A program built against the installed relief package (CMake: CMakeLists.txt beside it;
// pkg-config: `c++ -std=c++20 main.cpp $(pkg-config --cflags --libs relief)`). It generates a
// heightfield, picks an exact technique with maps from the registry, bakes its maps to
// DIR/consumer.maps.exr, reads them back, and checks that its tracer agrees with the reference
// (`exact`) on a fan of rays. Usage: relief_consumer DIR. Exit 0 when they agree.
#include <relief/core/generators.h>
#include <relief/techniques/registry.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace {

int fail(const relief::Error& error) {
    std::fprintf(stderr, "relief_consumer: %s\n", error.message.c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: relief_consumer DIR (for the baked maps)\n");
        return 1;
    }
    auto heightfield = relief::generateHeightfield("fbm", 64, 64, 1);
    if (!heightfield) return fail(heightfield.error());
    auto surface = std::make_shared<const relief::Surface>(
        std::make_shared<const relief::Heightfield>(std::move(*heightfield)), 8.0f,
        relief::EdgeMode::Clamp);

    // The first row besides the reference that is exact with its defaults and has maps.
    const relief::TechniqueInfo* chosen = nullptr;
    for (const relief::TechniqueInfo& info : relief::techniques())
        if (!info.reference && info.contract == relief::Contract::Exact && info.buildMaps) {
            chosen = &info;
            break;
        }
    if (!chosen) return fail({relief::ErrorKind::Runtime, "no exact technique with maps"});

    // Bake, write, read back (checked against this surface), trace with the file's maps.
    auto input = relief::techniqueInput(*chosen, surface, {});
    if (!input) return fail(input.error());
    auto maps = chosen->buildMaps(*input);
    if (!maps) return fail(maps.error());
    relief::MapFile file{relief::mapSourceOf(*surface), {std::move(*maps)}};
    const std::string path = std::string(argv[1]) + "/consumer.maps.exr";
    if (relief::Status written = relief::writeMapFile(path, file); !written)
        return fail(written.error());
    auto read = relief::readMapFile(path);
    if (!read) return fail(read.error());
    if (relief::Status same = relief::checkMapSource(path, read->source, file.source); !same)
        return fail(same.error());
    auto tracer = relief::createTracer(chosen->name, surface, {}, &*read, path);
    if (!tracer) return fail(tracer.error());
    auto reference = relief::createTracer(relief::referenceTechnique().name, surface);
    if (!reference) return fail(reference.error());

    // A fan of rays from above the box, down at about 40 degrees.
    std::vector<relief::Ray> rays;
    for (int k = 0; k < 256; ++k) {
        const float angle = 0.1f * float(k);
        relief::Ray ray;
        ray.origin = relief::vec3(32.0f, 32.0f, surface->maxZ() + 20.0f);
        ray.direction = glm::normalize(relief::vec3(std::cos(angle), std::sin(angle), -1.2f));
        rays.push_back(ray);
    }
    std::vector<relief::Hit> hits(rays.size()), expected(rays.size());
    relief::traceAll(**tracer, rays, hits);
    relief::traceAll(**reference, rays, expected);
    int hitCount = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        const bool agree = hits[k].hit == expected[k].hit &&
                           (!hits[k].hit || std::abs(hits[k].t - expected[k].t) <= 1e-3f);
        if (!agree) {
            std::fprintf(stderr, "relief_consumer: ray %zu: %s t=%g, exact t=%g\n", k,
                         std::string(chosen->name).c_str(), hits[k].t, expected[k].t);
            return 1;
        }
        hitCount += hits[k].hit;
    }
    if (hitCount == 0) return fail({relief::ErrorKind::Runtime, "no ray hit the surface"});
    std::printf("relief_consumer: %zu techniques; %s (maps from %s) agrees with %s on %zu rays, "
                "%d hits\n",
                relief::techniques().size(), std::string(chosen->name).c_str(), path.c_str(),
                std::string(relief::referenceTechnique().name).c_str(), rays.size(), hitCount);
    return 0;
}
