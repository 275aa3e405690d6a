#pragma once
// Embree 3 peer: the same triangles as S (DESIGN §2) as an Embree scene, for validating `exact`
// and for throughput comparisons. Clamp mode only: the mesh is the closed solid (top surface with
// its half-texel border strips, four side walls, bottom), so rays entering below S hit the wall
// as the convention says. Repeat mode has no finite mesh and is refused.
#include <relief/core/error.h>
#include <relief/core/math.h>
#include <relief/surface/surface.h>

#include <memory>
#include <span>
#include <vector>

namespace relief {

struct TriangleMesh {
    std::vector<vec3> vertices;
    std::vector<glm::uvec3> triangles;
};

// Triangles of the closed solid under S in clamp mode.
TriangleMesh buildSolidMesh(const Surface& surface);

class EmbreeScene {
public:
    static Result<std::unique_ptr<EmbreeScene>> create(const Surface& surface);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // rtcIntersect1 per ray.
    void intersect1(std::span<const Ray> rays, std::span<Hit> hits) const;
    // rtcIntersect16 on consecutive groups of 16 rays (the caller orders them as 4×4 tiles).
    void intersect16(std::span<const Ray> rays, std::span<Hit> hits) const;
    size_t triangleCount() const { return m_triangleCount; }

private:
    EmbreeScene() = default;
    void* m_device = nullptr;  // RTCDevice
    void* m_scene = nullptr;   // RTCScene
    size_t m_triangleCount = 0;
};

}  // namespace relief
