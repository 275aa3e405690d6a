#pragma once
// Option groups shared by the subcommands (DESIGN §3 names) and the glue that turns them into a
// Tracer (the Surface comes from render/surface_source.h).
#include <relief/core/error.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/camera.h>
#include <relief/render/surface_source.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

namespace relief::cli {

struct TechniqueOptions {
    std::string name = "exact";
    std::optional<int> maxSteps;
    std::vector<std::string> params;  // "name=value"
    std::string mapsPath;             // --maps FILE: baked maps instead of building them
    std::string backend = "cpu";
};

void addSurfaceOptions(CLI::App& app, SurfaceOptions& options);
void addTechniqueOptions(CLI::App& app, TechniqueOptions& options);
void addThreadsOption(CLI::App& app, int& threads);

// The orbit camera and the light, as render and view take them; the viewer narrows the ranges.
struct CameraLimits {
    float minDistance = 0.01f, maxDistance = 1000.0f;
    float minFov = 1.0f, maxFov = 170.0f;
};
void addCameraOptions(CLI::App& app, OrbitView& view, float& lightElevation, float& lightAzimuth,
                      const CameraLimits& limits = {});

// SurfaceOptions, loadHeightfield(options) and makeSurface(options, hf) come from
// render/surface_source.h, shared with the bench.
// Parameter overrides from --max-steps and --param NAME=VALUE.
Result<std::vector<std::pair<std::string, double>>> parameterOverrides(const TechniqueOptions& options);
// The technique's tracer, with its maps from --maps FILE when given (checked against the surface).
Result<std::unique_ptr<Tracer>> makeTracer(const TechniqueOptions& options,
                                           std::shared_ptr<const Surface> surface);
// The GLSL tracer of a technique (cli/gl_backend.cpp).
Result<std::unique_ptr<Tracer>> createGlBackendTracer(const TechniqueInfo& info,
                                                      const TechniqueInput& input);

// The one place where errors become messages and exit codes (0 ok, 1 bad arguments, 2 I/O,
// 3 invalid input, 4 runtime/GL, 5 unsupported).
int report(const Error& error);

// Commands register themselves on the app; their callbacks throw CommandFailed on error.
struct CommandFailed {
    Error error;
};
template <class T>
T orFail(Result<T> result) {
    if (!result) throw CommandFailed{result.error()};
    return std::move(*result);
}
inline void orFail(Status status) {
    if (!status) throw CommandFailed{status.error()};
}

// The command table (main.cpp): the global options and every command, on an empty app.
void addCommands(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addTraceCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addHelpCommand(CLI::App& app);
void addBakeCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addViewCommand(CLI::App& app);  // cmd_view.cpp: the interactive viewer (GLFW + ImGui)

}  // namespace relief::cli
