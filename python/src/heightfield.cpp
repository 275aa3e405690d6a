// relief.Heightfield: load (the CLI's loader and its options), generate, from_array, and the
// samples as a numpy view.
#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "module.h"

namespace relief::python {

namespace {

SurfaceOptions surfaceOptions(std::optional<double> depth, double depthRatio,
                              const std::string& edge) {
    SurfaceOptions o;
    if (depth) o.depth = float(*depth);
    o.depthRatio = float(depthRatio);
    o.edge = edge;
    return o;
}

// Samples Python may write: a mutable copy of what the loader made.
PyHeightfield made(std::shared_ptr<const Heightfield> hf, SurfaceOptions options) {
    PyHeightfield out{std::make_shared<Heightfield>(*hf), std::move(options)};
    out.surface();  // depth and edge refused now, not at the first trace
    return out;
}

// "LO:HI" as the CLI takes it, or a pair of numbers.
std::string rangeText(const py::object& range) {
    if (range.is_none()) return {};
    if (py::isinstance<py::str>(range)) return range.cast<std::string>();
    const char* expected = "(lo, hi) or 'LO:HI'";
    const auto pair = castArgument<std::vector<double>>(range, "height_range", expected);
    if (pair.size() != 2)
        raise(makeError(ErrorKind::BadArgument, "height_range: expected {}", expected));
    return fmt::format("{:.17g}:{:.17g}", pair[0], pair[1]);
}

// The CLI's source suffix for a window: @crop=X,Y,W,H (corner) or @centre=X,Y,W,H.
std::string windowSuffix(const py::object& crop, const py::object& centre) {
    if (!crop.is_none() && !centre.is_none())
        raise(makeError(ErrorKind::BadArgument, "crop and centre: give one window, not both"));
    const py::object& window = crop.is_none() ? centre : crop;
    if (window.is_none()) return {};
    const char* name = crop.is_none() ? "centre" : "crop";
    const char* expected = "four integers (x, y, w, h)";
    const auto v = castArgument<std::vector<int>>(window, name, expected);
    if (v.size() != 4) raise(makeError(ErrorKind::BadArgument, "{}: expected {}", name, expected));
    return fmt::format("@{}={},{},{},{}", name, v[0], v[1], v[2], v[3]);
}

PyHeightfield load(const std::string& path, std::optional<double> depth, double depthRatio,
                   const std::string& edge, bool invert, const py::object& heightRange,
                   const std::string& raw, const std::string& channel, int64_t maxSamples,
                   const py::object& crop, const py::object& centre) {
    SurfaceOptions o = surfaceOptions(depth, depthRatio, edge);
    o.source = path + windowSuffix(crop, centre);
    o.invert = invert;
    o.heightRange = rangeText(heightRange);
    o.raw = raw;
    o.channel = channel;
    o.maxSamples = maxSamples;
    return made(orRaise(withoutGil([&] { return loadHeightfield(o); })), o);
}

PyHeightfield generate(const std::string& name, int width, int height, uint64_t seed,
                       std::optional<double> depth, double depthRatio, const std::string& edge) {
    SurfaceOptions o = surfaceOptions(depth, depthRatio, edge);
    o.source = fmt::format("gen:{}:{}x{}:{}", name, width, height, seed);
    return made(orRaise(loadHeightfield(o)), o);
}

PyHeightfield fromArray(const py::object& input, std::optional<double> depth, double depthRatio,
                        const std::string& edge, const py::object& heightRange, bool normalize) {
    // Any dtype numpy can cast to float32, any strides: copied into the heightfield's samples.
    auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(input);
    if (!array) {
        PyErr_Clear();
        raise(makeError(ErrorKind::BadArgument, "from_array: expected a 2-D array of numbers"));
    }
    if (array.ndim() != 2)
        raise(makeError(ErrorKind::BadArgument,
                        "from_array: expected a 2-D array (rows, columns), got {} dimensions",
                        array.ndim()));
    const int64_t rows = array.shape(0), columns = array.shape(1);
    orRaise(checkDimensions("array", columns, rows));
    Heightfield hf;
    hf.width = int(columns);
    hf.height = int(rows);
    hf.samples.assign(array.data(), array.data() + array.size());
    const std::string range = rangeText(heightRange);
    if (!range.empty() && normalize)
        raise(makeError(ErrorKind::BadArgument, "from_array: height_range or normalize, not both"));
    if (!range.empty() || normalize) {
        double lo = 0.0, hi = 0.0;
        if (!range.empty() && (std::sscanf(range.c_str(), "%lf:%lf", &lo, &hi) != 2 || !(lo < hi)))
            raise(makeError(ErrorKind::BadArgument,
                            "height_range '{}': expected LO:HI with LO < HI", range));
        orRaise(normalizeSamples("array", hf.samples, hf.width, lo, hi));
    }
    SurfaceOptions o = surfaceOptions(depth, depthRatio, edge);
    o.source = fmt::format("array {}x{}", hf.width, hf.height);
    return made(std::make_shared<const Heightfield>(std::move(hf)), o);
}

}  // namespace

void bindHeightfield(py::module_& m) {
    using namespace pybind11::literals;
    py::class_<PyHeightfield>(
        m, "Heightfield",
        "A W x H grid of heights in [0, 1] with its relief depth (texels) and "
        "edge mode: the canonical surface of DESIGN section 2.")
        .def_static("load", &load, "path"_a, py::kw_only(), "depth"_a = py::none(),
                    "depth_ratio"_a = 0.1, "edge"_a = "clamp", "invert"_a = false,
                    "height_range"_a = py::none(), "raw"_a = "", "channel"_a = "luminance",
                    "max_samples"_a = kDefaultMaxSamples, "crop"_a = py::none(),
                    "centre"_a = py::none(),
                    "Reads a height map (PNG, JPEG, EXR, PFM, raw) or gen:NAME:WxH[:seed] with the "
                    "CLI's loader and its options (--depth, --depth-ratio, --edge, --invert, "
                    "--height-range, --raw, --channel, --max-samples, @crop=/@centre= windows). "
                    "OSError when the file cannot be read, ValueError for bad options or content.")
        .def_static("generate", &generate, "name"_a, "width"_a, "height"_a, py::kw_only(),
                    "seed"_a = 1, "depth"_a = py::none(), "depth_ratio"_a = 0.1, "edge"_a = "clamp",
                    "A built-in heightfield (core/generators.h: sine, peaks6, fbm, walls, spikes, "
                    "terraces, ramp, flat, bricks), the same as the CLI's gen:NAME:WxH:SEED.")
        .def_static("from_array", &fromArray, "array"_a, py::kw_only(), "depth"_a = py::none(),
                    "depth_ratio"_a = 0.1, "edge"_a = "clamp", "height_range"_a = py::none(),
                    "normalize"_a = false,
                    "Heights from a 2-D array (rows = y, columns = x), copied. Values must be in "
                    "[0, 1] unless height_range=(lo, hi) or normalize=True (the data's min/max) "
                    "rescales them.")
        .def_property_readonly("width", [](const PyHeightfield& h) { return h.samples->width; })
        .def_property_readonly("height", [](const PyHeightfield& h) { return h.samples->height; })
        .def_property_readonly(
            "depth", [](const PyHeightfield& h) { return h.surface()->depth(); },
            "relief depth D in texels")
        .def_property_readonly("edge", [](const PyHeightfield& h) { return h.options.edge; })
        .def_property_readonly("source", [](const PyHeightfield& h) { return h.options.source; })
        .def_property_readonly(
            "content_hash", [](const PyHeightfield& h) { return h.samples->contentHash(); },
            "the hash baked maps record (changes when heights change)")
        .def_property_readonly(
            "heights",
            [](py::object self) {
                const PyHeightfield& h = self.cast<const PyHeightfield&>();
                const auto w = py::ssize_t(h.samples->width), hgt = py::ssize_t(h.samples->height);
                // A view of the samples, writable, that keeps this Heightfield alive.
                return py::array_t<float>(
                    {hgt, w}, {w * py::ssize_t(sizeof(float)), py::ssize_t(sizeof(float))},
                    h.samples->samples.data(), self);
            },
            "the samples as a (height, width) float32 numpy view, no copy; writes are seen by the "
            "next call (values must stay in [0, 1])")
        .def("__repr__", [](const PyHeightfield& h) {
            return fmt::format("relief.Heightfield('{}', {}x{}, edge={})", h.options.source,
                               h.samples->width, h.samples->height, h.options.edge);
        });
}

}  // namespace relief::python
