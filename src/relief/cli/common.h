#pragma once
// Option groups shared by the subcommands (DESIGN §3 names) and the glue that turns them into a
// Surface and a Tracer.
#include <relief/core/error.h>
#include <relief/gl/gl_tracer.h>
#include <relief/io/heightfield_io.h>
#include <relief/render/camera.h>
#include <relief/render/surface_source.h>
#include <relief/surface/surface.h>
#include <relief/techniques/registry.h>
#include <relief/techniques/technique.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

namespace relief::cli {


struct TechniqueOptions {
    std::string name{referenceTechnique().name};  // the default row: the reference
    std::optional<int> maxSteps;       // the parameter with role IterationCap
    std::optional<double> phiMax;      // ... role PhiMax (degrees)
    std::string visibility;            // ... role Visibility: "all" (0) or "exterior" (1)
    std::vector<std::string> params;  // "name=value"
    std::string mapsPath;             // --maps FILE: baked maps instead of building them
    std::string backend = "cpu";
};

// CLI::Range lets NaN through (every comparison with it is false) and CLI11 reads "inf"; options
// that take a number check it with this: finite and in [lo, hi], the range in the message.
CLI::Validator finiteRange(double lo, double hi);
// More threads than this is a typo, not a machine (kMaxAzimuth: render/camera.h).
inline constexpr int kMaxThreads = 4096;

// The surface options include --max-memory (addMemoryOption): every command that loads a map.
void addSurfaceOptions(CLI::App& app, SurfaceOptions& options);
void addMemoryOption(CLI::App& app);
void addTechniqueOptions(CLI::App& app, TechniqueOptions& options);
void addThreadsOption(CLI::App& app, int& threads);
// --isa baseline|sse4|avx2|auto: the tracers' ISA for this run (core/isa.h; default RELIEF_ISA).
void addIsaOption(CLI::App& app);

// The orbit camera and the light, as render and view take them; the viewer narrows the ranges
// (CameraLimits: render/camera.h).
void addCameraOptions(CLI::App& app, OrbitView& view, float& lightElevation, float& lightAzimuth,
                      const CameraLimits& limits = {});
// The view part alone (--elevation, --azimuth, --distance, --fov): `relief rays`.
void addViewOptions(CLI::App& app, OrbitView& view, const CameraLimits& limits = {});
// --size WxH, 1 to 16384 each.
Result<ivec2> parseImageSize(const std::string& text);

// SurfaceOptions, loadHeightfield(options) and makeSurface(options, hf) come from
// render/surface_source.h, shared with the bench.
using Overrides = std::vector<std::pair<std::string, double>>;
Backend backendOf(const TechniqueOptions& options);
// The overrides of each technique from the role options (--max-steps, --phi-max, --visibility:
// the parameter with that role) and --param NAME=VALUE. What one technique lacks is left out for
// it, and is an error only when none of `infos` has it.
Result<std::vector<Overrides>> parameterOverrides(std::span<const TechniqueInfo* const> infos,
                                                  const TechniqueOptions& options);
Result<Overrides> parameterOverrides(const TechniqueInfo& info, const TechniqueOptions& options);
// --phi-max and --visibility on a command (trace, render, bake, view).
void addRoleOptions(CLI::App& app, TechniqueOptions& options);
// The technique's tracer on --backend, with its maps from --maps FILE when given (checked
// against the surface).
Result<std::unique_ptr<Tracer>> makeTracer(const TechniqueOptions& options,
                                           std::shared_ptr<const Surface> surface);
// The same for a row and parameter values already at hand (the viewer): its maps from `mapsPath`
// when not empty, the registry's techniqueInput(), then createTracer(backend, ...).
Result<std::unique_ptr<Tracer>> makeTracer(
    const TechniqueInfo& info, const std::vector<std::pair<std::string, double>>& overrides,
    const std::string& mapsPath, Backend backend, std::shared_ptr<const Surface> surface);

// --color FILE, or `--color gen`: the generator's own colour map (bricks) at the size of
// `source`; nothing for an empty path.
Result<std::optional<ImageRgb8>> loadColorOption(const std::string& path,
                                                 const std::string& source);

// The mesh preview's input (render --mesh, view --mesh): the row's parameters resolved and checked,
// its maps read from `mapsPath` when not empty (checked against the surface), else built.
struct PreviewInput {
    ParamValues params;
    TechniqueMaps maps;
};
Result<PreviewInput> previewInput(const TechniqueInfo& info, const Overrides& overrides,
                                  const std::string& mapsPath,
                                  std::shared_ptr<const Surface> surface);

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
// `relief ARGS...` in this process: parses, runs the command, returns its exit code.
int runCommandLine(int argc, char** argv);
void addInfoCommand(CLI::App& app);
void addTraceCommand(CLI::App& app);
void addRaysCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addHelpCommand(CLI::App& app);
void addBakeCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addServeCommand(CLI::App& app);  // cmd_serve.cpp: web/ and the shader library on localhost
void addViewCommand(CLI::App& app);  // cmd_view.cpp: the interactive viewer (GLFW + ImGui)

}  // namespace relief::cli
