#include <relief/preview/mesh.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <numbers>

namespace relief::preview {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// One quad: corner + s·a + t·b for (s, t) in [0, 1]², uv (s, t); counter-clockwise seen along
// cross(a, b).
void addQuad(Mesh& mesh, vec3 corner, vec3 a, vec3 b) {
    const uint32_t first = uint32_t(mesh.vertices.size());
    const vec3 n = glm::normalize(glm::cross(a, b));
    for (int k = 0; k < 4; ++k) {
        const float s = float(k & 1), t = float(k >> 1);
        mesh.vertices.push_back({corner + s * a + t * b, n, vec2(s, t), glm::vec4(0), vec2(0)});
    }
    for (uint32_t i : {0u, 1u, 3u, 0u, 3u, 2u}) mesh.indices.push_back(first + i);
}

// A grid of (columns + 1) × (rows + 1) vertices from `at(s, t)` (position, normal), s, t in
// [0, 1]; uv = (s, t). Triangles counter-clockwise when cross(dP/dt, dP/ds) points outside.
template <class At>
void addGrid(Mesh& mesh, int columns, int rows, At at) {
    const uint32_t first = uint32_t(mesh.vertices.size());
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= columns; ++i) {
            const vec2 uv(float(i) / float(columns), float(j) / float(rows));
            const auto [p, n] = at(uv.x, uv.y);
            mesh.vertices.push_back({p, n, uv, glm::vec4(0), vec2(0)});
        }
    const uint32_t stride = uint32_t(columns) + 1;
    for (uint32_t j = 0; j < uint32_t(rows); ++j)
        for (uint32_t i = 0; i < uint32_t(columns); ++i) {
            const uint32_t a = first + j * stride + i, b = a + 1, c = a + stride, d = c + 1;
            for (uint32_t v : {a, d, b, a, c, d}) mesh.indices.push_back(v);
        }
}

// Image convention: v grows downwards on a face seen from outside with z (or the face's "up")
// at the top, so a face shows its texture the way an image viewer does.
Mesh plane() {
    Mesh m;
    addQuad(m, vec3(-1, 1, 0), vec3(2, 0, 0), vec3(0, -2, 0));
    for (MeshVertex& v : m.vertices) v.normal = vec3(0, 0, 1);  // a, b above give -z: flip
    std::swap(m.indices[1], m.indices[2]);
    std::swap(m.indices[4], m.indices[5]);
    return m;
}

Mesh cube() {
    Mesh m;
    // Side faces: u along the face's right (seen from outside), v down; top: u = +x, v = -y;
    // bottom: u = +x, v = +y. Each quad is (corner, +u edge, +v edge) with cross(+v, +u) outside.
    struct Face {
        vec3 corner, a, b;
    };
    const Face faces[] = {
        {{-1, -1, 1}, {2, 0, 0}, {0, 0, -2}},  // front (-y)
        {{1, -1, 1}, {0, 2, 0}, {0, 0, -2}},   // right (+x)
        {{1, 1, 1}, {-2, 0, 0}, {0, 0, -2}},   // back (+y)
        {{-1, 1, 1}, {0, -2, 0}, {0, 0, -2}},  // left (-x)
        {{-1, 1, 1}, {2, 0, 0}, {0, -2, 0}},   // top (+z)
        {{-1, -1, -1}, {2, 0, 0}, {0, 2, 0}},  // bottom (-z)
    };
    for (const Face& f : faces) {
        addQuad(m, f.corner, f.a, f.b);
        // addQuad's winding faces cross(a, b); these faces look along cross(b, a).
        const size_t tri = m.indices.size() - 6;
        std::swap(m.indices[tri + 1], m.indices[tri + 2]);
        std::swap(m.indices[tri + 4], m.indices[tri + 5]);
        for (size_t k = m.vertices.size() - 4; k < m.vertices.size(); ++k)
            m.vertices[k].normal = -m.vertices[k].normal;
    }
    return m;
}

// Latitude-longitude sphere: u = longitude / 2π (eastwards seen from outside), v = 0 at the
// north pole (+z) to 1 at the south pole.
Mesh sphere() {
    Mesh m;
    addGrid(m, 64, 32, [](float s, float t) {
        const float phi = 2.0f * kPi * s, theta = kPi * t;
        const vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                     std::cos(theta));
        return std::pair(n, n);
    });
    return m;
}

// Side: u around (as the sphere), v from the top rim (0) to the bottom (1); caps planar.
Mesh cylinder() {
    Mesh m;
    addGrid(m, 64, 1, [](float s, float t) {
        const float phi = 2.0f * kPi * s;
        const vec3 n(std::cos(phi), std::sin(phi), 0.0f);
        return std::pair(n + vec3(0, 0, 1.0f - 2.0f * t), n);
    });
    for (float z : {1.0f, -1.0f}) {
        const uint32_t first = uint32_t(m.vertices.size());
        addGrid(m, 32, 1, [z](float s, float t) {
            const float phi = 2.0f * kPi * s, r = 1.0f - t;
            return std::pair(vec3(r * std::cos(phi), r * std::sin(phi), z), vec3(0, 0, z));
        });
        for (size_t k = first; k < m.vertices.size(); ++k) {
            MeshVertex& v = m.vertices[k];
            v.uv = vec2(0.5f + 0.5f * v.position.x, 0.5f - 0.5f * z * v.position.y);
        }
        if (z > 0)  // the grid winds along cross(dP/dt, dP/ds), downwards on the top cap
            for (size_t k = m.indices.size() - 6 * 32; k < m.indices.size(); k += 3)
                std::swap(m.indices[k + 1], m.indices[k + 2]);
    }
    return m;
}

// Where an accessor's elements lie: checked against its buffer view and buffer.
struct AccessorBytes {
    const unsigned char* first = nullptr;
    size_t stride = 0, count = 0;
    int componentType = 0, componentSize = 0;
};

Result<AccessorBytes> accessorBytes(const tinygltf::Model& model, int index, int components,
                                    const std::string& path, std::string_view what) {
    auto bad = [&](std::string_view why) {
        return makeError(ErrorKind::InvalidInput, "{}: {}: {}", path, what, why);
    };
    if (index < 0 || size_t(index) >= model.accessors.size()) return bad("no such accessor");
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    if (tinygltf::GetNumComponentsInType(uint32_t(a.type)) != components)
        return bad(fmt::format("expected {} component(s)", components));
    if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size())
        return bad("no buffer view (sparse accessors are not read)");
    const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) return bad("no buffer");
    const std::vector<unsigned char>& data = model.buffers[size_t(view.buffer)].data;
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (size <= 0) return bad("unknown component type");
    const size_t element = size_t(size) * size_t(components);
    const size_t stride = view.byteStride ? view.byteStride : element;
    const size_t begin = view.byteOffset + a.byteOffset;
    if (begin > data.size() || a.count > data.size() ||
        (a.count > 0 &&
         (data.size() - begin < element || (a.count - 1) * stride > data.size() - begin - element)))
        return bad("runs past its buffer");
    return AccessorBytes{data.data() + begin, stride, a.count, a.componentType, size};
}

// The accessor's elements as floats (normalized integers decoded), `components` each.
Result<std::vector<float>> readAccessor(const tinygltf::Model& model, int index, int components,
                                        const std::string& path, std::string_view what) {
    auto bytes = accessorBytes(model, index, components, path, what);
    if (!bytes) return bytes.error();
    std::vector<float> out;
    out.reserve(bytes->count * size_t(components));
    for (size_t k = 0; k < bytes->count; ++k)
        for (int c = 0; c < components; ++c) {
            const unsigned char* p =
                bytes->first + k * bytes->stride + size_t(c * bytes->componentSize);
            float value = 0.0f;
            switch (bytes->componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT:
                    std::memcpy(&value, p, 4);
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    value = float(*p) / 255.0f;
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t u;
                    std::memcpy(&u, p, 2);
                    value = float(u) / 65535.0f;
                    break;
                }
                default:
                    return makeError(ErrorKind::InvalidInput,
                                     "{}: {}: component type not float, UNORM8 or UNORM16", path,
                                     what);
            }
            out.push_back(value);
        }
    return out;
}

Result<std::vector<uint32_t>> readIndices(const tinygltf::Model& model, int index,
                                          const std::string& path) {
    auto bytes = accessorBytes(model, index, 1, path, "indices");
    if (!bytes) return bytes.error();
    if (bytes->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        bytes->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        bytes->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return makeError(ErrorKind::InvalidInput, "{}: indices: not unsigned integers", path);
    std::vector<uint32_t> out;
    out.reserve(bytes->count);
    for (size_t k = 0; k < bytes->count; ++k) {
        uint32_t v = 0;  // glTF is little endian, as this machine
        std::memcpy(&v, bytes->first + k * bytes->stride, size_t(bytes->componentSize));
        out.push_back(v);
    }
    return out;
}

// The node's world matrices, for every node that holds `mesh` (the default scene's, else all).
void collectInstances(const tinygltf::Model& model, int node, const glm::mat4& parent, int mesh,
                      std::vector<glm::mat4>& out, int depth = 0) {
    if (node < 0 || size_t(node) >= model.nodes.size() || depth > 64) return;
    const tinygltf::Node& n = model.nodes[size_t(node)];
    glm::mat4 local(1.0f);
    if (n.matrix.size() == 16) {
        for (int k = 0; k < 16; ++k) local[k / 4][k % 4] = float(n.matrix[size_t(k)]);
    } else {
        if (n.translation.size() == 3)
            local = glm::translate(local, vec3(float(n.translation[0]), float(n.translation[1]),
                                               float(n.translation[2])));
        if (n.rotation.size() == 4)
            local *= glm::mat4_cast(glm::quat(float(n.rotation[3]), float(n.rotation[0]),
                                              float(n.rotation[1]), float(n.rotation[2])));
        if (n.scale.size() == 3)
            local =
                glm::scale(local, vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
    }
    const glm::mat4 world = parent * local;
    if (n.mesh == mesh) out.push_back(world);
    for (int child : n.children) collectInstances(model, child, world, mesh, out, depth + 1);
}

}  // namespace

void computeTangentFrames(Mesh& mesh, bool keepGivenTangents) {
    const size_t n = mesh.vertices.size();
    std::vector<vec3> du(n, vec3(0)), dv(n, vec3(0));
    std::vector<vec2> scale(n, vec2(0));
    std::vector<float> weight(n, 0.0f);
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
        const uint32_t i[3] = {mesh.indices[k], mesh.indices[k + 1], mesh.indices[k + 2]};
        const MeshVertex &a = mesh.vertices[i[0]], &b = mesh.vertices[i[1]],
                         &c = mesh.vertices[i[2]];
        const vec3 e1 = b.position - a.position, e2 = c.position - a.position;
        const vec2 t1 = b.uv - a.uv, t2 = c.uv - a.uv;
        const float det = t1.x * t2.y - t2.x * t1.y;
        const float area = 0.5f * glm::length(glm::cross(e1, e2));
        if (std::abs(det) < 1e-12f || area <= 0.0f) continue;
        const vec3 dPdu = (t2.y * e1 - t1.y * e2) / det, dPdv = (t1.x * e2 - t2.x * e1) / det;
        for (uint32_t v : i) {
            du[v] += area * dPdu;
            dv[v] += area * dPdv;
            scale[v] += area * vec2(glm::length(dPdu), glm::length(dPdv));
            weight[v] += area;
        }
    }
    for (size_t v = 0; v < n; ++v) {
        MeshVertex& m = mesh.vertices[v];
        m.uvScale = weight[v] > 0 ? scale[v] / weight[v] : vec2(1);
        m.uvScale = glm::max(m.uvScale, vec2(1e-6f));  // poles: the frame is only a direction
        if (keepGivenTangents && m.tangent.w != 0.0f) continue;
        vec3 t = du[v] - m.normal * glm::dot(m.normal, du[v]);
        if (glm::dot(t, t) < 1e-20f)  // degenerate UVs: any direction in the plane
            t = glm::cross(m.normal, std::abs(m.normal.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0));
        t = glm::normalize(t);
        const float w = glm::dot(glm::cross(m.normal, t), dv[v]) < 0.0f ? -1.0f : 1.0f;
        m.tangent = glm::vec4(t, w);
    }
}

void normalizeMesh(Mesh& mesh) {
    if (mesh.vertices.empty()) return;
    vec3 lo(kInfinity), hi(-kInfinity);
    for (const MeshVertex& v : mesh.vertices) {
        lo = glm::min(lo, v.position);
        hi = glm::max(hi, v.position);
    }
    const vec3 centre = 0.5f * (lo + hi);
    float radius = 0.0f;
    for (const MeshVertex& v : mesh.vertices)
        radius = std::max(radius, glm::length(v.position - centre));
    const float s = radius > 0.0f ? 1.0f / radius : 1.0f;
    for (MeshVertex& v : mesh.vertices) {
        v.position = (v.position - centre) * s;
        v.uvScale *= s;
    }
}

Result<Mesh> builtinMesh(std::string_view name) {
    Mesh mesh;
    if (name == "plane")
        mesh = plane();
    else if (name == "cube")
        mesh = cube();
    else if (name == "sphere")
        mesh = sphere();
    else if (name == "cylinder")
        mesh = cylinder();
    else
        return makeError(ErrorKind::BadArgument,
                         "--mesh '{}': expected plane, cube, sphere, cylinder or a .gltf/.glb file",
                         name);
    computeTangentFrames(mesh);
    normalizeMesh(mesh);
    return mesh;
}

Result<Mesh> loadGltf(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return makeError(ErrorKind::Io, "{}: cannot open (no such file)", path);
    tinygltf::TinyGLTF loader;
    // The file's images are not used (the heightfield's maps texture the mesh).
    loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int,
                             const unsigned char*, int, void*) { return true; },
                          nullptr);
    tinygltf::Model model;
    std::string error, warning;
    const bool binary = path.size() >= 4 && path.substr(path.size() - 4) == ".glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                           : loader.LoadASCIIFromFile(&model, &error, &warning, path);
    if (!ok)
        return makeError(ErrorKind::InvalidInput, "{}: not a valid glTF file: {}", path,
                         error.empty() ? warning : error);
    if (model.meshes.empty()) return makeError(ErrorKind::InvalidInput, "{}: no mesh", path);
    std::vector<glm::mat4> instances;
    for (size_t node = 0; node < model.nodes.size(); ++node) {
        bool isChild = false;
        for (const tinygltf::Node& n : model.nodes)
            isChild |=
                std::find(n.children.begin(), n.children.end(), int(node)) != n.children.end();
        if (!isChild) collectInstances(model, int(node), glm::mat4(1.0f), 0, instances);
    }
    if (instances.empty()) instances.push_back(glm::mat4(1.0f));
    Mesh mesh;
    bool tangentsGiven = true;
    for (const glm::mat4& world : instances)
        for (const tinygltf::Primitive& p : model.meshes[0].primitives) {
            if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) continue;
            auto attribute = [&](const char* name) {
                auto it = p.attributes.find(name);
                return it == p.attributes.end() ? -1 : it->second;
            };
            if (attribute("POSITION") < 0 || attribute("TEXCOORD_0") < 0) continue;
            auto positions = readAccessor(model, attribute("POSITION"), 3, path, "POSITION");
            if (!positions) return positions.error();
            auto uvs = readAccessor(model, attribute("TEXCOORD_0"), 2, path, "TEXCOORD_0");
            if (!uvs) return uvs.error();
            const size_t count = positions->size() / 3;
            if (uvs->size() / 2 != count)
                return makeError(ErrorKind::InvalidInput,
                                 "{}: POSITION and TEXCOORD_0 differ in count", path);
            std::vector<float> normals, tangents;
            if (attribute("NORMAL") >= 0) {
                auto n = readAccessor(model, attribute("NORMAL"), 3, path, "NORMAL");
                if (!n) return n.error();
                normals = std::move(*n);
            }
            if (attribute("TANGENT") >= 0) {
                auto t = readAccessor(model, attribute("TANGENT"), 4, path, "TANGENT");
                if (!t) return t.error();
                tangents = std::move(*t);
            }
            tangentsGiven &= tangents.size() == 4 * count;
            const glm::mat3 linear(world), normalMatrix = glm::transpose(glm::inverse(linear));
            const uint32_t first = uint32_t(mesh.vertices.size());
            for (size_t k = 0; k < count; ++k) {
                MeshVertex v{};
                v.position = vec3(world * glm::vec4((*positions)[3 * k], (*positions)[3 * k + 1],
                                                    (*positions)[3 * k + 2], 1.0f));
                v.uv = vec2((*uvs)[2 * k], (*uvs)[2 * k + 1]);
                if (normals.size() == 3 * count)
                    v.normal =
                        glm::normalize(normalMatrix * vec3(normals[3 * k], normals[3 * k + 1],
                                                           normals[3 * k + 2]));
                if (tangents.size() == 4 * count)
                    v.tangent =
                        glm::vec4(glm::normalize(linear * vec3(tangents[4 * k], tangents[4 * k + 1],
                                                               tangents[4 * k + 2])),
                                  tangents[4 * k + 3] < 0 ? -1.0f : 1.0f);
                mesh.vertices.push_back(v);
            }
            std::vector<uint32_t> indices;
            if (p.indices >= 0) {
                auto read = readIndices(model, p.indices, path);
                if (!read) return read.error();
                indices = std::move(*read);
            } else {
                for (uint32_t k = 0; k < count; ++k) indices.push_back(k);
            }
            for (uint32_t i : indices) {
                if (i >= count)
                    return makeError(ErrorKind::InvalidInput, "{}: index {} past {} vertices", path,
                                     i, count);
                mesh.indices.push_back(first + i);
            }
            if (normals.size() != 3 * count)  // flat normals from the triangles, summed
                for (size_t k = 0; k + 2 < indices.size(); k += 3) {
                    MeshVertex* v[3] = {&mesh.vertices[first + indices[k]],
                                        &mesh.vertices[first + indices[k + 1]],
                                        &mesh.vertices[first + indices[k + 2]]};
                    const vec3 n = glm::cross(v[1]->position - v[0]->position,
                                              v[2]->position - v[0]->position);
                    for (MeshVertex* x : v) x->normal += n;
                }
        }
    mesh.indices.resize(mesh.indices.size() / 3 * 3);
    if (mesh.indices.empty())
        return makeError(ErrorKind::InvalidInput,
                         "{}: the first mesh has no triangles with POSITION and TEXCOORD_0", path);
    for (MeshVertex& v : mesh.vertices)
        if (glm::dot(v.normal, v.normal) > 0)
            v.normal = glm::normalize(v.normal);
        else
            v.normal = vec3(0, 0, 1);
    computeTangentFrames(mesh, tangentsGiven);
    normalizeMesh(mesh);
    return mesh;
}

Result<Mesh> loadMesh(const std::string& spec) {
    const std::string ext = std::filesystem::path(spec).extension().string();
    if (ext == ".gltf" || ext == ".glb") return loadGltf(spec);
    return builtinMesh(spec);
}

}  // namespace relief::preview
