#pragma once
// What trace() and render() share: a technique's tracer as the Python arguments name it, the
// orbit camera, and hit statistics as a dict.
#include <relief/gl/gl_tracer.h>
#include <relief/render/camera.h>
#include <relief/render/compare.h>
#include <relief/techniques/technique.h>

#include <optional>

#include "module.h"

namespace relief::python {

// Checked with the GIL held (tracerSpec); create() touches no Python object.
struct TracerSpec {
    const TechniqueInfo* info = nullptr;
    Overrides overrides;
    std::shared_ptr<const Surface> surface;
    Backend backend = Backend::Cpu;
    std::optional<PyMaps> maps;
    // The CLI's makeTracer: techniqueInput (maps from `maps`, else built), createTracer(backend).
    Result<std::unique_ptr<Tracer>> create() const;
};
TracerSpec tracerSpec(const PyHeightfield& hf, const std::string& technique, const py::object& maps,
                      const std::string& backend, int threads, const py::kwargs& params);

// Python's numbers (double) as the camera's floats.
OrbitView orbitView(double elevation, double azimuth, double distance, double fov);
Camera cameraOf(const PyHeightfield& hf, const OrbitView& view, std::pair<int, int> size);
py::dict statsDict(const ErrorStats& stats);

}  // namespace relief::python
