#pragma once
// Meshes for the material preview: the built-in plane, cube, sphere and cylinder (generated with
// UVs and tangents), and glTF 2.0 files (.gltf / .glb through tinygltf: the first mesh's
// triangles, node transforms applied; tangents from the file, else computed from the UVs).
//
// Conventions: z up; a mesh is centred on the origin and scaled to a bounding radius of 1, so the
// orbit camera's distance is in mesh diameters. uv (0, 0) is the texture's first texel; a face's
// tangent points along +u, its bitangent along +v (tangent.w = ±1: bitangent = w·cross(n, t)).
#include <relief/core/error.h>
#include <relief/core/math.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace relief::preview {

struct MeshVertex {
    vec3 position;
    vec3 normal;
    vec2 uv;
    glm::vec4 tangent;  // unit, along +u; w = handedness of +v
    // World length of one uv unit along the tangent and the bitangent here (|dP/du|, |dP/dv|):
    // relief depth is a fraction of the u extent (docs/engine.md), so the renderer needs them.
    vec2 uvScale;
};

struct Mesh {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;  // triangles, counter-clockwise seen from outside
};

// The names builtinMesh() takes.
inline constexpr std::string_view kBuiltinMeshes[] = {"plane", "cube", "sphere", "cylinder"};

// A built-in mesh, or BadArgument naming the choices.
Result<Mesh> builtinMesh(std::string_view name);

// A glTF file: Io when it cannot be read, InvalidInput when it is not valid glTF or has no
// triangles with positions and UVs.
Result<Mesh> loadGltf(const std::string& path);

// `spec`: a built-in name or a path ending in .gltf / .glb.
Result<Mesh> loadMesh(const std::string& spec);

// From the triangles' UVs: every vertex's uvScale (area-weighted |dP/du|, |dP/dv|) and, unless
// keepGivenTangents and the vertex has one (w != 0), its tangent (per-vertex sums of dP/du,
// Gram-Schmidt against the normal, handedness from dP/dv).
void computeTangentFrames(Mesh& mesh, bool keepGivenTangents = false);

// Centres the mesh on its bounding box and scales it to a bounding radius of 1.
void normalizeMesh(Mesh& mesh);

}  // namespace relief::preview
