// relief._relief: the compiled half of the Python module `relief` (python/relief/__init__.py).
#include "module.h"

#include <relief/core/parallel.h>
#include <relief/techniques/technique.h>

#include <cmath>
#include <optional>

namespace relief::python {

void raise(const Error& error) {
    PyObject* type = PyExc_RuntimeError;
    switch (error.kind) {
        case ErrorKind::BadArgument:
        case ErrorKind::InvalidInput:
        case ErrorKind::Unsupported:
            type = PyExc_ValueError;
            break;
        case ErrorKind::Io:
            type = PyExc_OSError;
            break;
        case ErrorKind::Runtime:
            type = PyExc_RuntimeError;
            break;
    }
    py::object exception = py::reinterpret_borrow<py::object>(type)(error.message);
    exception.attr("exit_code") = int(error.kind);
    PyErr_SetObject(type, exception.ptr());
    throw py::error_already_set();
}

std::shared_ptr<const Surface> PyHeightfield::surface() const {
    const Heightfield& hf = *samples;
    for (size_t k = 0; k < hf.samples.size(); ++k) {
        const float v = hf.samples[k];
        if (!(v >= 0.0f && v <= 1.0f))  // NaN fails too
            raise(makeError(ErrorKind::InvalidInput,
                            "heights[{}, {}] = {}: heights must be finite and in [0, 1]",
                            k / size_t(hf.width), k % size_t(hf.width), v));
    }
    return orRaise(makeSurface(options, samples));
}

void PyMaps::check(const Surface& surface) const {
    orRaise(checkMapSource(name, file->source, mapSourceOf(surface)));
}

Overrides overridesOf(const py::kwargs& params) {
    Overrides overrides;
    for (const auto& [key, value] : params) {
        std::string name = py::cast<std::string>(key);
        for (char& c : name)
            if (c == '_') c = '-';
        for (const auto& [given, _] : overrides)
            if (given == name)  // max_steps=4 and **{"max-steps": 5}: the last would win silently
                raise(makeError(ErrorKind::BadArgument, "parameter '{}' is given twice", name));
        // Numbers only (float("3") would take a string); py::float_ fails on e.g. an array.
        std::optional<double> number;
        if (!py::isinstance<py::str>(value) && !py::isinstance<py::bytes>(value)) {
            try {
                number = py::cast<double>(py::float_(py::reinterpret_borrow<py::object>(value)));
            } catch (py::error_already_set&) {  // fetched: the Python error is cleared
            }
        }
        if (!number)
            raise(makeError(ErrorKind::BadArgument, "parameter '{}': expected a number, got {}",
                            name,
                            py::str(py::type::of(value).attr("__name__")).cast<std::string>()));
        overrides.emplace_back(name, *number);
    }
    return overrides;
}

void checkThreads(int threads) {
    if (threads < 0)
        raise(makeError(ErrorKind::BadArgument, "threads {}: 0 (all cores) or a positive count",
                        threads));
}

}  // namespace relief::python

PYBIND11_MODULE(_relief, m) {
    namespace rp = relief::python;
    m.doc() = "relief: ray casting of heightfields with published techniques (see docs/python.md)";
    m.attr("__version__") = RELIEF_VERSION;
    rp::bindHeightfield(m);
    rp::bindTechniques(m);
    rp::bindTrace(m);
    rp::bindRender(m);
}
