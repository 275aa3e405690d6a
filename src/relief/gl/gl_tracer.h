#pragma once
// The GL backend: a technique's GLSL tracer (TechniqueInfo::glsl, the twin of its C++ `trace`)
// run as a compute shader in a headless OpenGL 4.5 context (egl_context.h: Mesa surfaceless /
// llvmpipe, or an EGL device such as a headless NVIDIA GPU).
//
// Programs are assembled from the generated interface (shader_interface.h), the common_*.glsl
// files, the technique's file and an entry point (main_rays.glsl for ray batches,
// main_camera.glsl for camera frames whose rays are made on the GPU). The heights are
// Surface::paddedHeights() in a storage buffer, so the GPU reads the same numbers as the CPU.
//
// Parameters and maps are checked as on the CPU, without a CPU tracer: input.params resolved
// (resolveParams, techniqueInput), then the row's `check` (what its create refuses beyond that,
// baked input.maps included). A technique with maps (TechniqueInfo::buildMaps) gets input.maps
// when given, else the maps built once by info.buildMaps. Every MapArray goes into
// one storage buffer at kMapsBinding, and the GLSL reads them through declarations generated
// from the TechniqueMaps themselves (shader_interface.h: kMap<Name>, mapTexel, sizes, channels),
// so a map's layout is spelled only by the C++ that builds it.
#include <relief/gl/camera.h>
#include <relief/techniques/technique.h>

#include <memory>
#include <string>
#include <vector>

namespace relief {

using GlCamera = gl::CameraUniforms;

// The GL context in use ("EGL_PLATFORM_SURFACELESS_MESA: Mesa / llvmpipe (...) / OpenGL 4.5 ..."),
// or the error that names every EGL platform tried.
Result<std::string> glBackendDescription();

// A Tracer that runs info.glsl on the GPU. traceBatch uploads the rays, dispatches, and reads
// hit, t, position, steps and fetches back. Calls from several threads are serialized on the one
// GL context, so large batches are much faster than many small ones.
Result<std::unique_ptr<Tracer>> createGlTracer(const TechniqueInfo& info,
                                               const TechniqueInput& input);

// Where rays are traced (`--backend cpu|gl`).
enum class Backend : uint8_t { Cpu, Gl };

// The one place that chooses the backend (CLI, viewer): info.create on the CPU, createGlTracer
// on the GL backend; `input` as the registry's techniqueInput() makes it.
Result<std::unique_ptr<Tracer>> createTracer(Backend backend, const TechniqueInfo& info,
                                             const TechniqueInput& input);

struct GlTimingOptions {
    int frames = 10;       // timed frames
    int warmupFrames = 2;  // untimed, first (compilation, caches)
};

// Milliseconds per frame measured with glFinish after each frame and a CPU clock (DESIGN §8).
struct GlFrameTiming {
    double msPerFrame = 0.0;   // mean over the timed frames
    double msMin = 0.0;        // fastest timed frame
    int frames = 0;
    double meanSteps = 0.0;    // per pixel, last frame (0 for the mesh)
    double hitFraction = 0.0;  // pixels that hit (mesh: pixels covered)
    std::string device;        // glBackendDescription()
};

// One technique on the GPU for camera frames (the bench's GL rows): the heights and maps are
// uploaded and the camera program (main_camera.glsl) compiled once, at creation; then frames are
// timed and traced as often as asked, with any camera. The primary rays are generated on the GPU.
class GlCameraTracer {
public:
    virtual ~GlCameraTracer() = default;
    // Frames timed with glFinish after each; nothing is read back between frames.
    virtual Result<GlFrameTiming> timeFrames(const GlCamera& camera,
                                             const GlTimingOptions& options) = 0;
    // One frame read back: camera.width × camera.height hits, row 0 at the top; pixel (px, py)
    // is the ray gl::cameraRay(camera, px, py).
    virtual Result<std::vector<Hit>> traceFrame(const GlCamera& camera) = 0;
    // Other parameters (e.g. an iteration cap) for the same surface and maps: they are uniforms
    // (TraceUniforms::params), so nothing is uploaded or compiled again. Checked as at creation.
    virtual Status setParams(const TechniqueInput& input) = 0;
};

// Checks and maps as createGlTracer.
Result<std::unique_ptr<GlCameraTracer>> createGlCameraTracer(const TechniqueInfo& info,
                                                             const TechniqueInput& input);

// One-shot forms of GlCameraTracer (each creates one): timeFrames and traceFrame.
Result<GlFrameTiming> timeGlFrame(const TechniqueInfo& info, const TechniqueInput& input,
                                  const GlCamera& camera, const GlTimingOptions& options = {});
Result<std::vector<Hit>> traceGlCamera(const TechniqueInfo& info, const TechniqueInput& input,
                                       const GlCamera& camera);

// The rasterized peer: S as a triangle mesh (two triangles per cell along the lower diagonal,
// plus the side walls in clamp mode), one indexed draw into an offscreen framebuffer of the
// camera's size, with depth test and flat shading; timed like GlCameraTracer::timeFrames.
Result<GlFrameTiming> timeRasterizedMesh(const Surface& surface, const GlCamera& camera,
                                         const GlTimingOptions& options = {});

}  // namespace relief
