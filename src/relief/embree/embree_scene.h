#pragma once
// Embree 3 peer: the same triangles as S (DESIGN §2) as an Embree scene, for validating `exact`
// and for throughput comparisons. Clamp mode only: the mesh is the closed solid (top surface with
// its half-texel border strips, four side walls, bottom), so rays entering below S hit the wall
// as the convention says. Repeat mode has no finite mesh and is refused. The same scene type can
// hold the heightfield as a user geometry instead (heightfield_geometry.h), for comparisons.
#include <relief/core/error.h>
#include <relief/core/math.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <embree3/rtcore.h>

#include <atomic>
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
// Attaches buildSolidMesh(surface) to `scene` as one triangle geometry (not committed); its geomID,
// and its triangle count in `triangles` when given.
Result<unsigned> attachSolidMesh(RTCScene scene, const Surface& surface, size_t* triangles = nullptr);
// Attaches any mesh the same way (e.g. the texel boxes' faces, surface/texel_boxes.h).
Result<unsigned> attachMesh(RTCScene scene, const TriangleMesh& mesh, size_t* triangles = nullptr);

// Counts the bytes a device holds (Embree reports every allocation and free to a monitor): the
// BVH, the geometry buffers and Embree's own bookkeeping.
class DeviceMemory {
public:
    void attach(RTCDevice device);
    int64_t bytes() const { return m_bytes.load(std::memory_order_relaxed); }

private:
    static bool monitor(void* self, ssize_t bytes, bool post);
    std::atomic<int64_t> m_bytes{0};
};

class EmbreeScene {
public:
    static Result<std::unique_ptr<EmbreeScene>> create(const Surface& surface);
    // Any triangle mesh (a surface other than S, e.g. the texel boxes).
    static Result<std::unique_ptr<EmbreeScene>> create(const TriangleMesh& mesh);
    // The heightfield as one user geometry over `tracer` (embree::attachTracer) instead of triangles.
    static Result<std::unique_ptr<EmbreeScene>> createUserGeometry(std::shared_ptr<const Surface> surface,
                                                                   std::shared_ptr<const Tracer> tracer);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // rtcIntersect1 per ray.
    void intersect1(std::span<const Ray> rays, std::span<Hit> hits) const;
    // rtcIntersect16 on consecutive groups of 16 rays (the caller orders them as 4×4 tiles).
    void intersect16(std::span<const Ray> rays, std::span<Hit> hits) const;
    // Occlusion queries on [0, ray.tMax] (rtcOccluded1; rtcOccluded16 on groups of 16 as
    // intersect16): occluded[k] = 1 when anything lies on ray k's segment.
    void occluded1(std::span<const Ray> rays, std::span<uint8_t> occluded) const;
    void occluded16(std::span<const Ray> rays, std::span<uint8_t> occluded) const;
    size_t triangleCount() const { return m_triangleCount; }
    // Bytes the scene's device held after the build (BVH + buffers), by its memory monitor.
    int64_t embreeBytes() const { return m_builtBytes; }

private:
    struct Geometry;  // the user geometry, when there is one
    EmbreeScene() = default;
    static Result<std::unique_ptr<EmbreeScene>> withScene();
    void commit();
    DeviceMemory m_memory;
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
    std::unique_ptr<Geometry> m_geometry;
    size_t m_triangleCount = 0;
    int64_t m_builtBytes = 0;
};

}  // namespace relief
