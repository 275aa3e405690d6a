#pragma once
// Everything that crosses the C++/GLSL boundary: uniform blocks, buffer records, binding points
// and constants. Each is defined here once; glslInterface() generates the GLSL declarations that
// every program starts with, so the shaders never spell a layout or a constant themselves. A
// technique's own constants come from its registry row (TechniqueInfo::glslConstants).
#include <relief/gl/std140.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <string>
#include <vector>

namespace relief::gl {

// Binding points (uniform blocks and storage buffers have separate binding spaces).
inline constexpr int kSurfaceBinding = 0;  // uniform SurfaceUniforms
inline constexpr int kTraceBinding = 1;    // uniform TraceUniforms
inline constexpr int kCameraBinding = 2;   // uniform CameraUniforms
inline constexpr int kMeshBinding = 3;     // uniform MeshUniforms
inline constexpr int kRaysBinding = 0;     // buffer Rays { RayRecord rays[]; }
inline constexpr int kHitsBinding = 1;     // buffer Hits { HitRecord hits[]; }
inline constexpr int kHeightsBinding = 2;  // buffer Heights { float heights[]; } (padded)
inline constexpr int kMapsBinding = 3;     // buffer Maps { float maps[]; } (every MapArray)

inline constexpr int kLocalSize = 64;  // invocations per work group, ray batches
inline constexpr int kTileSize = 8;    // work group side, camera frames (8×8)
inline constexpr int kMaxParams = 16;  // technique parameters, in ParamSpec order

// Surface: size W×H, depth D, max height, edge mode (kEdgeClamp / kEdgeRepeat).
#define RELIEF_GL_SURFACE_UNIFORMS(F, S) \
    F(S, ivec2, size)                    \
    F(S, float, depth)                   \
    F(S, float, maxZ)                    \
    F(S, int32_t, edge)
RELIEF_GL_BLOCK(SurfaceUniforms, RELIEF_GL_SURFACE_UNIFORMS);

// One dispatch: the number of rays and the technique's parameters by index (kParam<Name>).
#define RELIEF_GL_TRACE_UNIFORMS(F, S) \
    F(S, int32_t, rayCount)            \
    F(S, Vec4x4, params)
RELIEF_GL_BLOCK(TraceUniforms, RELIEF_GL_TRACE_UNIFORMS);

// A pinhole camera: eye and an orthonormal basis; pixel (px, py), row 0 at the top, looks along
// forward + sx·right + sy·up with sx, sy in [-tanHalfFovY·aspect, ..], [-tanHalfFovY, ..].
#define RELIEF_GL_CAMERA_UNIFORMS(F, S) \
    F(S, vec3, eye)                     \
    F(S, float, tanHalfFovY)            \
    F(S, vec3, right)                   \
    F(S, float, aspect)                 \
    F(S, vec3, up)                      \
    F(S, int32_t, width)                \
    F(S, vec3, forward)                 \
    F(S, int32_t, height)
RELIEF_GL_BLOCK(CameraUniforms, RELIEF_GL_CAMERA_UNIFORMS);

// The rasterized peer: clip from texel space, and the light direction for its shading.
#define RELIEF_GL_MESH_UNIFORMS(F, S) \
    F(S, glm::mat4, clipFromTexel)    \
    F(S, vec3, lightDirection)
RELIEF_GL_BLOCK(MeshUniforms, RELIEF_GL_MESH_UNIFORMS);

// std430 records of the ray and hit buffers (32 bytes each).
#define RELIEF_GL_RAY_RECORD(F, S) \
    F(S, vec3, origin)             \
    F(S, float, tMax)              \
    F(S, vec3, direction)          \
    F(S, float, pad0)
RELIEF_GL_BLOCK(RayRecord, RELIEF_GL_RAY_RECORD);

#define RELIEF_GL_HIT_RECORD(F, S) \
    F(S, vec3, position)           \
    F(S, float, t)                 \
    F(S, int32_t, hit)             \
    F(S, int32_t, steps)           \
    F(S, int32_t, fetches)         \
    F(S, int32_t, pad0)
RELIEF_GL_BLOCK(HitRecord, RELIEF_GL_HIT_RECORD);

inline RayRecord toRecord(const Ray& ray) {
    RayRecord r;
    r.origin = ray.origin;
    r.tMax = ray.tMax;
    r.direction = ray.direction;
    return r;
}

inline Hit fromRecord(const HitRecord& r) {
    Hit hit;
    hit.hit = r.hit != 0;
    hit.t = hit.hit ? r.t : kInfinity;
    hit.position = hit.hit ? r.position : vec3(0.0f);
    hit.steps = r.steps;
    hit.fetches = r.fetches;
    return hit;
}

SurfaceUniforms surfaceUniforms(const Surface& surface);

// The technique's parameters in ParamSpec order; an error if it has more than kMaxParams.
Result<TraceUniforms> traceUniforms(const TechniqueInfo& info, const ParamValues& params);

// "max-steps" → "kParamMaxSteps": the GLSL name of a parameter's index.
std::string glslParamName(std::string_view paramName);

// ---- Maps (TechniqueMaps) ----
// All arrays of a technique's maps live in ONE storage buffer (binding kMapsBinding), one after
// the other in natural name order ("level2" before "level10"), each row-major with its channels
// interleaved, exactly MapArray::data. One buffer rather than one per array: the walks pick an
// array at run time (a pyramid level, a ray class), which one buffer makes a table lookup instead
// of a switch over blocks, and a deep pyramid would exceed the 16 storage blocks per stage that
// some drivers allow. The GLSL side is generated (glslMapInterface): per array `kMap<Name>` (its
// index; "level0" → kMapLevel0, "ccx+" → kMapCcxPlus) and `#define RELIEF_MAP_<NAME>` (to test
// for an optional array), tables kMapOffset / kMapWidth / kMapHeight / kMapChannels, the
// accessor `mapTexel(map, x, y, channel)`, and one `const float kMapParam<Name>` per numeric
// map parameter, named as glslParamName names parameters ("cone-max" → kMapParamConeMax).

// "ccx+" → "CcxPlus", "level0" → "Level0": the GLSL spelling of an array or parameter name.
std::string glslMapName(std::string_view name);

// The arrays in buffer order (natural name order).
std::vector<const MapArray*> mapOrder(const TechniqueMaps& maps);

// The buffer contents: the arrays of mapOrder concatenated.
std::vector<float> packMaps(const TechniqueMaps& maps);

// The GLSL declarations described above ("const int kMapCount = 0;" when there are none).
std::string glslMapInterface(const TechniqueMaps* maps);

// The GLSL text every program starts with (after #version): constants, the records and the
// uniform blocks. With `info`, also the row's glslConstants (`const int NAME = V;` or
// `const float NAME = V;`) and one `const int kParam<Name> = index;` per parameter; with `maps`,
// the map declarations (glslMapInterface).
std::string glslInterface(const TechniqueInfo* info = nullptr,
                          const TechniqueMaps* maps = nullptr);

}  // namespace relief::gl
