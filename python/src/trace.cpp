// relief.trace(), relief.camera_rays() and relief.compare(): rays in and hits out as numpy
// arrays, traced by the registry's tracers (CPU or GL) with the GIL released.
#include "trace.h"

#include <relief/core/parallel.h>
#include <relief/io/ray_io.h>
#include <relief/render/camera.h>
#include <relief/render/compare.h>
#include <relief/techniques/registry.h>

#include <cmath>
#include <limits>

namespace relief::python {

namespace {

// One row of a trace result (numpy structured dtype: hit, t, point, steps, fetches).
struct HitRecord {
    bool hit;
    float t;
    float point[3];
    int32_t steps;
    int32_t fetches;
};

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// (N, 3) numbers, converted and made contiguous (a copy when they are not already).
Doubles rowsOf3(const py::object& input, const char* what) {
    auto array = Doubles::ensure(input);
    if (!array) {
        PyErr_Clear();
        raise(makeError(ErrorKind::BadArgument, "{}: expected an (N, 3) array of numbers", what));
    }
    if (array.ndim() != 2 || array.shape(1) != 3)
        raise(makeError(ErrorKind::BadArgument, "{}: expected an (N, 3) array, got shape {}", what,
                        py::str(array.attr("shape")).cast<std::string>()));
    return array;
}

std::vector<Ray> raysOf(const py::object& origins, const py::object& directions,
                        const py::object& tMax) {
    const Doubles o = rowsOf3(origins, "origins"), d = rowsOf3(directions, "directions");
    const size_t n = size_t(o.shape(0));
    if (size_t(d.shape(0)) != n)
        raise(
            makeError(ErrorKind::BadArgument, "origins has {} rows, directions {}", n, d.shape(0)));
    std::vector<double> limits;
    if (!tMax.is_none()) {
        const auto t = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(tMax);
        if (!t || (t.ndim() != 0 && !(t.ndim() == 1 && size_t(t.shape(0)) == n))) {
            PyErr_Clear();
            raise(makeError(ErrorKind::BadArgument,
                            "t_max: expected a number or an array of {} numbers (one per ray)", n));
        }
        limits.assign(t.data(), t.data() + t.size());
    }
    std::vector<Ray> rays(n);
    const double* po = o.data();
    const double* pd = d.data();
    for (size_t k = 0; k < n; ++k) {
        // The checks of a ray file's lines (io/ray_io.h), in float as there.
        const double v[7] = {float(po[3 * k]), float(po[3 * k + 1]), float(po[3 * k + 2]),
                             float(pd[3 * k]), float(pd[3 * k + 1]), float(pd[3 * k + 2]), 0.0};
        auto ray = checkedRay(v, 6);
        if (!ray)
            raise(makeError(ErrorKind::BadArgument, "row {} of origins/directions: {}", k,
                            ray.error().message));
        rays[k] = *ray;
        if (!limits.empty()) {
            const double t = limits[limits.size() == 1 ? 0 : k];
            if (!(t >= 0.0))  // NaN fails too
                raise(makeError(ErrorKind::BadArgument,
                                "t_max of ray {} is {}: expected >= 0 (inf: no limit)", k, t));
            rays[k].tMax = t >= double(std::numeric_limits<float>::max()) ? kInfinity : float(t);
        }
    }
    return rays;
}

py::array_t<HitRecord> hitRecords(const std::vector<Hit>& hits) {
    py::array_t<HitRecord> out(py::ssize_t(hits.size()));
    HitRecord* r = out.mutable_data();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (size_t k = 0; k < hits.size(); ++k) {
        const Hit& h = hits[k];
        r[k].hit = h.hit;
        r[k].t = h.hit ? h.t : kInfinity;
        for (int a = 0; a < 3; ++a) r[k].point[a] = h.hit ? h.position[a] : nan;
        r[k].steps = h.steps;
        r[k].fetches = h.fetches;
    }
    return out;
}

py::array_t<HitRecord> trace(const PyHeightfield& hf, const py::object& origins,
                             const py::object& directions, const std::string& technique,
                             const py::object& maps, const py::object& tMax,
                             const std::string& backend, int threads, const py::kwargs& params) {
    std::vector<Ray> rays = raysOf(origins, directions, tMax);
    TracerSpec spec = tracerSpec(hf, technique, maps, backend, threads, params);
    std::vector<Hit> hits(rays.size());
    orRaise(withoutGil([&]() -> Status {
        ThreadLimit limit(threads);
        auto tracer = spec.create();
        if (!tracer) return tracer.error();
        traceFromAnywhere(**tracer, *spec.surface, rays, hits);
        return {};
    }));
    return hitRecords(hits);
}

py::tuple cameraRays(const PyHeightfield& hf, double elevation, double azimuth, double distance,
                     double fov, std::pair<int, int> size) {
    const OrbitView view = orbitView(elevation, azimuth, distance, fov);
    const Camera camera = cameraOf(hf, view, size);
    const std::vector<Ray> rays = primaryRays(camera);
    std::vector<float> o(3 * rays.size()), d(3 * rays.size());
    for (size_t k = 0; k < rays.size(); ++k)
        for (int a = 0; a < 3; ++a) {
            o[3 * k + a] = rays[k].origin[a];
            d[3 * k + a] = rays[k].direction[a];
        }
    const auto n = py::ssize_t(rays.size());
    return py::make_tuple(ownedArray(std::move(o), {n, 3}), ownedArray(std::move(d), {n, 3}));
}

// A field of a trace result, a dict or anything indexable by name, as a flat array.
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> field(const py::object& hits,
                                                                const char* name,
                                                                const char* what) {
    py::object column;
    try {
        column = hits[py::str(name)];
    } catch (py::error_already_set&) {
        raise(makeError(ErrorKind::BadArgument, "{}: has no field '{}' (expected hit, t, steps)",
                        what, name));
    }
    auto array = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(column);
    if (!array || array.ndim() != 1) {
        PyErr_Clear();
        raise(makeError(ErrorKind::BadArgument, "{}['{}']: expected a 1-D array", what, name));
    }
    return array;
}

std::vector<Hit> hitsOf(const py::object& hits, const char* what) {
    const auto hit = field<bool>(hits, "hit", what);
    const auto t = field<float>(hits, "t", what);
    const auto steps = field<int32_t>(hits, "steps", what);
    bool hasFetches = true;
    try {
        py::object column = hits[py::str("fetches")];  // item access is lazy until assigned
    } catch (py::error_already_set&) {
        hasFetches = false;
    }
    std::vector<Hit> out(size_t(hit.shape(0)));
    if (t.shape(0) != hit.shape(0) || steps.shape(0) != hit.shape(0))
        raise(makeError(ErrorKind::BadArgument, "{}: hit, t and steps differ in length", what));
    const int32_t* fetches = nullptr;
    py::array_t<int32_t, py::array::c_style | py::array::forcecast> f;
    if (hasFetches) {
        f = field<int32_t>(hits, "fetches", what);
        if (f.shape(0) != hit.shape(0))
            raise(makeError(ErrorKind::BadArgument, "{}: fetches differs in length", what));
        fetches = f.data();
    }
    for (size_t k = 0; k < out.size(); ++k) {
        out[k].hit = hit.data()[k];
        out[k].t = t.data()[k];
        out[k].steps = steps.data()[k];
        out[k].fetches = fetches ? fetches[k] : 0;
        if (out[k].hit && !std::isfinite(out[k].t))
            raise(
                makeError(ErrorKind::BadArgument, "{}: ray {} hits at t = {}", what, k, out[k].t));
    }
    return out;
}

py::dict summaryDict(const Summary& s) {
    py::dict d;
    d["count"] = s.count;
    d["mean"] = s.mean;
    d["p95"] = s.p95;
    d["p99"] = s.p99;
    d["max"] = s.max;
    return d;
}

py::dict compare(const py::object& reference, const py::object& hits) {
    Image<Hit> ref, run;
    ref.pixels = hitsOf(reference, "reference");
    run.pixels = hitsOf(hits, "hits");
    if (ref.pixels.size() != run.pixels.size())
        raise(makeError(ErrorKind::BadArgument, "reference has {} rays, hits {}", ref.pixels.size(),
                        run.pixels.size()));
    ref.width = run.width = int(ref.pixels.size());
    ref.height = run.height = 1;
    return statsDict(compareHits(run, ref));
}

}  // namespace

py::dict statsDict(const ErrorStats& stats) {
    py::dict d;
    d["rays"] = stats.pixels;
    d["hits"] = stats.hits;
    d["covered"] = stats.covered;
    d["both_hit"] = stats.bothHit;
    d["wrong"] = stats.wrong;
    d["wrong_rate"] = stats.wrongRate();
    d["covered_wrong_rate"] = stats.coveredWrongRate();
    d["error"] = summaryDict(stats.error);
    d["steps"] = summaryDict(stats.steps);
    d["covered_steps"] = summaryDict(stats.coveredSteps);
    d["fetches"] = summaryDict(stats.fetches);
    return d;
}

TracerSpec tracerSpec(const PyHeightfield& hf, const std::string& technique, const py::object& maps,
                      const std::string& backend, int threads, const py::kwargs& params) {
    checkThreads(threads);
    if (backend != "cpu" && backend != "gl")
        raise(makeError(ErrorKind::BadArgument, "backend '{}': cpu or gl", backend));
    TracerSpec spec;
    spec.info = orRaise(lookupTechnique(technique));
    spec.overrides = overridesOf(params);
    spec.surface = hf.surface();
    spec.backend = backend == "gl" ? Backend::Gl : Backend::Cpu;
    if (!maps.is_none()) {
        if (!py::isinstance<PyMaps>(maps))
            raise(makeError(ErrorKind::BadArgument,
                            "maps: expected relief.Maps (relief.bake or "
                            "relief.Maps.load), got {}",
                            py::str(py::type::of(maps).attr("__name__")).cast<std::string>()));
        spec.maps = maps.cast<PyMaps>();
        // Never accepted unread (the CLI's --maps rule).
        if (!spec.info->buildMaps)
            raise(makeError(ErrorKind::Unsupported, "maps: {} reads no maps", spec.info->name));
        spec.maps->check(*spec.surface);
    }
    return spec;
}

Result<std::unique_ptr<Tracer>> TracerSpec::create() const {
    auto input = techniqueInput(*info, surface, overrides, maps ? maps->file.get() : nullptr,
                                maps ? maps->name : std::string());
    if (!input) return input.error();
    return createTracer(backend, *info, *input);
}

OrbitView orbitView(double elevation, double azimuth, double distance, double fov) {
    return OrbitView{float(elevation), float(azimuth), float(distance), float(fov)};
}

Camera cameraOf(const PyHeightfield& hf, const OrbitView& view, std::pair<int, int> size) {
    orRaise(checkOrbitView(view, size.first, size.second));
    return Camera(view, *hf.surface(), size.first, size.second);
}

void bindTrace(py::module_& m) {
    using namespace pybind11::literals;
    PYBIND11_NUMPY_DTYPE(HitRecord, hit, t, point, steps, fetches);
    m.def("trace", &trace, "heightfield"_a, "origins"_a, "directions"_a, py::kw_only(),
          "technique"_a = "cone", "maps"_a = py::none(), "t_max"_a = py::none(),
          "backend"_a = "cpu", "threads"_a = 0,
          "Traces rays, one per row of the (N, 3) arrays origins and directions (texel space; any "
          "numeric dtype and strides, converted; directions are normalized) with a technique's "
          "tracer on backend 'cpu' or 'gl', multithreaded, the GIL released. Parameters as "
          "keywords. t_max: None, a number, or one per ray; the ray is clipped to it (Ray::tMax) "
          "and a hit beyond it (a tracer that overshoots) is reported as a miss. Far origins "
          "are brought to the box first, as relief trace does. Returns a structured array with "
          "fields hit (bool), t (float32, inf on a miss), point (3 float32, NaN on a miss), "
          "steps, fetches (int32). ValueError for bad arrays (naming the row), parameters or "
          "stale maps.");
    m.def("camera_rays", &cameraRays, "heightfield"_a, py::kw_only(), "elevation"_a = 40.2,
          "azimuth"_a = 30.0, "distance"_a = 1.2, "fov"_a = 45.0,
          "size"_a = std::pair<int, int>(800, 600),
          "The primary rays of the orbit camera that relief render and the bench views use "
          "(render/camera.h): (origins, directions), each (W*H, 3) float32, pixel rows top to "
          "bottom. size = (width, height).");
    m.def("compare", &compare, "reference"_a, "hits"_a,
          "The bench's and render's hit statistics (render/compare.h: compareHits) of `hits` "
          "against `reference`, both with fields hit, t, steps (and fetches): a trace result, a "
          "dict of arrays, or anything indexable by those names. A ray is wrong when hit/miss "
          "differs or |t - t_ref| > 0.5 texel. Returns rays, hits, covered, both_hit, wrong, "
          "wrong_rate, covered_wrong_rate and summaries (count, mean, p95, p99, max) of error, "
          "steps, covered_steps and fetches.");
}

}  // namespace relief::python
