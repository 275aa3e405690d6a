#pragma once
// The Python module's glue (python/src): relief errors as Python exceptions, keyword parameters
// as registry overrides, and the objects Python holds. Only conversions live here; the work is
// the library's.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <relief/core/error.h>
#include <relief/core/heightfield.h>
#include <relief/io/map_file.h>
#include <relief/render/surface_source.h>
#include <relief/surface/surface.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace relief::python {

namespace py = pybind11;

// The one place where ErrorKind becomes an exception type: ValueError (bad argument, invalid
// input, unsupported), OSError (I/O), RuntimeError (runtime/GL), with relief's message and the
// CLI's exit code as `exit_code`. Called with the GIL held.
[[noreturn]] void raise(const Error& error);
template <class T>
T orRaise(Result<T> result) {
    if (!result) raise(result.error());
    return std::move(*result);
}
inline void orRaise(const Status& status) {
    if (!status) raise(status.error());
}

// A heightfield as Python holds it: the samples it owns (`heights` is a numpy view of them, so
// they may change between calls) and the surface options (depth, edge) a Surface is made with
// at each call.
struct PyHeightfield {
    std::shared_ptr<Heightfield> samples;
    SurfaceOptions options;
    // The samples checked (finite, in [0, 1]: numpy may have written anything) and the surface.
    std::shared_ptr<const Surface> surface() const;
};

// Baked maps: a whole map file (one or more techniques), and the name messages give it.
struct PyMaps {
    std::shared_ptr<const MapFile> file;
    std::string name;
    // Refuses maps baked from another heightfield, size, edge mode or depth (checkMapSource).
    void check(const Surface& surface) const;
};

// `value` as T, or ValueError "<what>: expected <expected>" (not pybind11's RuntimeError).
template <class T>
T castArgument(const py::handle& value, const char* what, const char* expected) {
    try {
        return value.cast<T>();
    } catch (const py::cast_error&) {
        raise(makeError(ErrorKind::BadArgument, "{}: expected {}", what, expected));
    }
}

using Overrides = std::vector<std::pair<std::string, double>>;
// Keyword parameters as overrides: snake_case names become the registry's kebab-case
// (max_steps -> max-steps); values must be numbers (bool counts as 0 or 1).
Overrides overridesOf(const py::kwargs& params);

// Runs `work` (which touches no Python object) with the GIL released; its Result is checked by
// the caller, with the GIL held again.
template <class F>
auto withoutGil(F&& work) {
    py::gil_scoped_release release;
    return work();
}

// Threads: 0 = all cores, else a positive count.
void checkThreads(int threads);

// Wraps a vector's storage in a numpy array without copying (the array owns it).
template <class T>
py::array_t<T> ownedArray(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, owned->data(), free);
}

void bindHeightfield(py::module_& m);
void bindTechniques(py::module_& m);
void bindTrace(py::module_& m);
void bindRender(py::module_& m);

}  // namespace relief::python
