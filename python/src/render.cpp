// relief.render(): a technique's image (relief render's per-pixel path) as numpy arrays.
#include <relief/core/memory_budget.h>
#include <relief/core/parallel.h>
#include <relief/render/renderer.h>
#include <relief/techniques/registry.h>

#include <cstring>

#include "trace.h"

namespace relief::python {

namespace {

template <class T, class F>
py::array_t<T> imageOf(const Image<Hit>& hits, F value) {
    std::vector<T> out(hits.pixels.size());
    for (size_t k = 0; k < out.size(); ++k) out[k] = value(hits.pixels[k]);
    return ownedArray(std::move(out), {hits.height, hits.width});
}

py::dict render(const PyHeightfield& hf, const std::string& technique, double elevation,
                double azimuth, double distance, double fov, std::pair<int, int> size,
                double lightElevation, double lightAzimuth, bool shadows, bool error,
                const py::object& maps, const std::string& backend, int threads,
                const py::kwargs& params) {
    const TracerSpec spec = tracerSpec(hf, technique, maps, backend, threads, params);
    if (spec.info->image != ImageMethod::PerPixel)
        raise(makeError(ErrorKind::Unsupported,
                        "render: {} draws its image with its own method (the visibility-curve "
                        "renderer): use the CLI, relief render -t {}",
                        spec.info->name, spec.info->name));
    const Camera camera = cameraOf(hf, orbitView(elevation, azimuth, distance, fov), size);
    const struct {
        const char* name;
        double value, limit;
    } lights[] = {{"light_elevation", lightElevation, 90.0},
                  {"light_azimuth", lightAzimuth, kMaxAzimuth}};
    for (const auto& l : lights)
        if (!(std::abs(l.value) <= l.limit))  // NaN fails too
            raise(makeError(ErrorKind::BadArgument,
                            "{} {:g} is not a finite number from {:g} to {:g}", l.name, l.value,
                            -l.limit, l.limit));
    const int64_t pixels = int64_t(size.first) * size.second;
    orRaise(reserveMemory(pixels * int64_t(sizeof(Hit)) + renderPeakBytes(pixels, shadows),
                          fmt::format("render size {}x{}", size.first, size.second)));
    Shading shading;
    shading.towardsLight = directionFromAngles(float(lightElevation), float(lightAzimuth));
    shading.shadows = shadows;
    RenderResult result;
    Image<Hit> reference;
    orRaise(withoutGil([&]() -> Status {
        ThreadLimit limit(threads);
        auto tracer = spec.create();
        if (!tracer) return tracer.error();
        result = relief::render(*spec.surface, camera, **tracer, shading);
        if (error) {
            auto exact = createTracer(referenceTechnique().name, spec.surface);
            if (!exact) return exact.error();
            reference = tracePrimary(camera, **exact);
        }
        return {};
    }));
    const Image<Hit>& hits = result.hits;
    py::dict out;
    std::vector<uint8_t> rgb(3 * result.color.pixels.size());
    std::memcpy(rgb.data(), result.color.pixels.data(), rgb.size());
    out["color"] = ownedArray(std::move(rgb), {hits.height, hits.width, 3});
    out["hit"] =
        imageOf<uint8_t>(hits, [](const Hit& h) { return uint8_t(h.hit); }).attr("astype")("bool");
    out["depth"] = imageOf<float>(hits, [](const Hit& h) { return h.hit ? h.t : kInfinity; });
    out["steps"] = imageOf<int32_t>(hits, [](const Hit& h) { return h.steps; });
    out["fetches"] = imageOf<int32_t>(hits, [](const Hit& h) { return h.fetches; });
    if (error) {
        out["error"] =
            ownedArray(std::move(errorValues(hits, reference).pixels), {hits.height, hits.width});
        out["stats"] = statsDict(compareHits(hits, reference));
    }
    return out;
}

}  // namespace

void bindRender(py::module_& m) {
    using namespace pybind11::literals;
    m.def("render", &render, "heightfield"_a, "technique"_a = "exact", py::kw_only(),
          "elevation"_a = 40.2, "azimuth"_a = 30.0, "distance"_a = 1.2, "fov"_a = 45.0,
          "size"_a = std::pair<int, int>(800, 600), "light_elevation"_a = 45.0,
          "light_azimuth"_a = 135.0, "shadows"_a = false, "error"_a = true, "maps"_a = py::none(),
          "backend"_a = "cpu", "threads"_a = 0,
          "Renders a technique's image as relief render does (orbit camera, Lambert shading, one "
          "primary ray per pixel: the rays of camera_rays with the same view). Returns a dict of "
          "numpy images, row 0 at the top: color (H, W, 3) uint8, hit (H, W) bool, depth (H, W) "
          "float32 (t, inf where missed), steps and fetches (H, W) int32, and with error=True "
          "error (H, W) float32 (|t - t_exact|; NaN where both miss, inf where wrong) and stats "
          "(relief.compare against exact).");
}

}  // namespace relief::python
