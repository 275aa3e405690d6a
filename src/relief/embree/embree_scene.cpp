#include <relief/embree/embree_scene.h>

#include <relief/embree/heightfield_geometry.h>

#include <cstring>

namespace relief {

TriangleMesh buildSolidMesh(const Surface& s) {
    const int W = s.width(), H = s.height();
    TriangleMesh mesh;
    // Grid vertices at x = 0, 0.5, 1.5, ..., W-0.5, W (and likewise y): sample centres plus the
    // box faces, where the border strips end.
    auto coord = [](int a, int n) { return a == 0 ? 0.0f : (a == n + 1 ? float(n) : float(a) - 0.5f); };
    const int nx = W + 2, ny = H + 2;
    auto index = [nx](int a, int b) { return unsigned(b * nx + a); };
    for (int b = 0; b < ny; ++b)
        for (int a = 0; a < nx; ++a)
            mesh.vertices.emplace_back(coord(a, W), coord(b, H),
                                       s.sampleZ(std::clamp(a - 1, 0, W - 1), std::clamp(b - 1, 0, H - 1)));
    for (int b = 0; b + 1 < ny; ++b) {
        for (int a = 0; a + 1 < nx; ++a) {
            const unsigned v00 = index(a, b), v10 = index(a + 1, b), v01 = index(a, b + 1),
                           v11 = index(a + 1, b + 1);
            const float z00 = mesh.vertices[v00].z, z10 = mesh.vertices[v10].z,
                        z01 = mesh.vertices[v01].z, z11 = mesh.vertices[v11].z;
            if (z00 + z11 <= z10 + z01) {
                mesh.triangles.emplace_back(v00, v10, v11);
                mesh.triangles.emplace_back(v00, v11, v01);
            } else {
                mesh.triangles.emplace_back(v00, v10, v01);
                mesh.triangles.emplace_back(v10, v11, v01);
            }
        }
    }
    // Side walls: for each boundary edge of the top, a quad down to z = 0.
    auto wall = [&mesh](unsigned top0, unsigned top1) {
        const vec3 a = mesh.vertices[top0], b = mesh.vertices[top1];
        const unsigned base = unsigned(mesh.vertices.size());
        mesh.vertices.emplace_back(a.x, a.y, 0.0f);
        mesh.vertices.emplace_back(b.x, b.y, 0.0f);
        mesh.triangles.emplace_back(top0, top1, base + 1);
        mesh.triangles.emplace_back(top0, base + 1, base);
    };
    for (int a = 0; a + 1 < nx; ++a) {
        wall(index(a, 0), index(a + 1, 0));
        wall(index(a, ny - 1), index(a + 1, ny - 1));
    }
    for (int b = 0; b + 1 < ny; ++b) {
        wall(index(0, b), index(0, b + 1));
        wall(index(nx - 1, b), index(nx - 1, b + 1));
    }
    const unsigned base = unsigned(mesh.vertices.size());
    mesh.vertices.emplace_back(0.0f, 0.0f, 0.0f);
    mesh.vertices.emplace_back(float(W), 0.0f, 0.0f);
    mesh.vertices.emplace_back(float(W), float(H), 0.0f);
    mesh.vertices.emplace_back(0.0f, float(H), 0.0f);
    mesh.triangles.emplace_back(base, base + 1, base + 2);
    mesh.triangles.emplace_back(base, base + 2, base + 3);
    return mesh;
}

Result<unsigned> attachSolidMesh(RTCScene scene, const Surface& surface, size_t* triangles) {
    if (surface.edge() != EdgeMode::Clamp)
        return makeError(ErrorKind::Unsupported, "Embree peer: only clamp edge mode has a finite mesh");
    return attachMesh(scene, buildSolidMesh(surface), triangles);
}

Result<unsigned> attachMesh(RTCScene scene, const TriangleMesh& mesh, size_t* triangles) {
    RTCDevice device = rtcGetSceneDevice(scene);  // retained: released below
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcReleaseDevice(device);
    if (!geometry) return makeError(ErrorKind::Runtime, "Embree: rtcNewGeometry failed");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) {
        rtcReleaseGeometry(geometry);
        return makeError(ErrorKind::Runtime, "Embree: buffer allocation failed ({} triangles)",
                         mesh.triangles.size());
    }
    std::memcpy(vertices, mesh.vertices.data(), mesh.vertices.size() * sizeof(vec3));
    std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3));
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    if (triangles) *triangles = mesh.triangles.size();
    return id;
}

void DeviceMemory::attach(RTCDevice device) { rtcSetDeviceMemoryMonitorFunction(device, monitor, this); }

bool DeviceMemory::monitor(void* self, ssize_t bytes, bool) {
    static_cast<DeviceMemory*>(self)->m_bytes.fetch_add(int64_t(bytes), std::memory_order_relaxed);
    return true;  // count, never refuse
}

struct EmbreeScene::Geometry {
    embree::HeightfieldGeometry handle;
};

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::withScene() {
    std::unique_ptr<EmbreeScene> self(new EmbreeScene());
    self->m_device = rtcNewDevice(nullptr);
    if (!self->m_device) return makeError(ErrorKind::Runtime, "Embree: rtcNewDevice failed");
    self->m_memory.attach(self->m_device);
    self->m_scene = rtcNewScene(self->m_device);
    rtcSetSceneFlags(self->m_scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(self->m_scene, RTC_BUILD_QUALITY_HIGH);
    return self;
}

void EmbreeScene::commit() {
    rtcCommitScene(m_scene);
    m_builtBytes = m_memory.bytes();
}

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::create(const Surface& surface) {
    if (surface.edge() != EdgeMode::Clamp)
        return makeError(ErrorKind::Unsupported, "Embree peer: only clamp edge mode has a finite mesh");
    auto self = withScene();
    if (!self) return self.error();
    if (auto id = attachSolidMesh((*self)->m_scene, surface, &(*self)->m_triangleCount); !id) return id.error();
    (*self)->commit();
    return self;
}

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::create(const TriangleMesh& mesh) {
    auto self = withScene();
    if (!self) return self.error();
    if (auto id = attachMesh((*self)->m_scene, mesh, &(*self)->m_triangleCount); !id) return id.error();
    (*self)->commit();
    return self;
}

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::createUserGeometry(std::shared_ptr<const Surface> surface,
                                                                     std::shared_ptr<const Tracer> tracer) {
    auto self = withScene();
    if (!self) return self.error();
    auto handle = embree::attachTracer((*self)->m_scene, std::move(surface), std::move(tracer));
    if (!handle) return handle.error();
    (*self)->m_geometry = std::make_unique<Geometry>(Geometry{std::move(*handle)});
    (*self)->commit();
    return self;
}

EmbreeScene::~EmbreeScene() {
    m_geometry.reset();
    if (m_scene) rtcReleaseScene(m_scene);
    if (m_device) rtcReleaseDevice(m_device);
}

namespace {
Hit hitFrom(const Ray& ray, float tfar, unsigned geomID) {
    Hit hit;
    if (geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.hit = true;
    hit.t = tfar;
    hit.position = ray.at(tfar);
    return hit;
}

// One ray as Embree's [0, tMax] segment; shared by the intersection and occlusion queries.
RTCRay embreeRay(const Ray& r) {
    RTCRay ray;
    ray.org_x = r.origin.x; ray.org_y = r.origin.y; ray.org_z = r.origin.z;
    ray.dir_x = r.direction.x; ray.dir_y = r.direction.y; ray.dir_z = r.direction.z;
    ray.tnear = 0.0f;
    ray.tfar = r.tMax;
    ray.time = 0.0f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    return ray;
}

// rays[first, first + n) into lanes 0..n-1 of a packet, the last ray repeated in the invalid lanes.
void fillPacket(RTCRay16& packet, int (&valid)[16], std::span<const Ray> rays, size_t first, size_t n) {
    for (size_t k = 0; k < 16; ++k) {
        valid[k] = k < n ? -1 : 0;
        const RTCRay r = embreeRay(rays[first + std::min(k, n - 1)]);
        packet.org_x[k] = r.org_x; packet.org_y[k] = r.org_y; packet.org_z[k] = r.org_z;
        packet.dir_x[k] = r.dir_x; packet.dir_y[k] = r.dir_y; packet.dir_z[k] = r.dir_z;
        packet.tnear[k] = r.tnear;
        packet.tfar[k] = r.tfar;
        packet.time[k] = r.time;
        packet.mask[k] = r.mask;
        packet.id[k] = unsigned(k);
        packet.flags[k] = r.flags;
    }
}

RTCIntersectContext coherentContext() {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    return context;
}
}  // namespace

void EmbreeScene::intersect1(std::span<const Ray> rays, std::span<Hit> hits) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t k = 0; k < rays.size(); ++k) {
        RTCRayHit rh;
        rh.ray = embreeRay(rays[k]);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(m_scene, &context, &rh);
        hits[k] = hitFrom(rays[k], rh.ray.tfar, rh.hit.geomID);
    }
}

void EmbreeScene::intersect16(std::span<const Ray> rays, std::span<Hit> hits) const {
    RTCIntersectContext context = coherentContext();
    for (size_t first = 0; first < rays.size(); first += 16) {
        const size_t n = std::min<size_t>(16, rays.size() - first);
        alignas(64) int valid[16];
        alignas(64) RTCRayHit16 rh;
        fillPacket(rh.ray, valid, rays, first, n);
        for (size_t k = 0; k < 16; ++k) {
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, m_scene, &context, &rh);
        for (size_t k = 0; k < n; ++k)
            hits[first + k] = hitFrom(rays[first + k], rh.ray.tfar[k], rh.hit.geomID[k]);
    }
}

// Embree marks an occluded ray by setting its tfar to -inf.
void EmbreeScene::occluded1(std::span<const Ray> rays, std::span<uint8_t> occluded) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t k = 0; k < rays.size(); ++k) {
        RTCRay ray = embreeRay(rays[k]);
        rtcOccluded1(m_scene, &context, &ray);
        occluded[k] = ray.tfar < 0.0f;
    }
}

void EmbreeScene::occluded16(std::span<const Ray> rays, std::span<uint8_t> occluded) const {
    RTCIntersectContext context = coherentContext();
    for (size_t first = 0; first < rays.size(); first += 16) {
        const size_t n = std::min<size_t>(16, rays.size() - first);
        alignas(64) int valid[16];
        alignas(64) RTCRay16 ray;
        fillPacket(ray, valid, rays, first, n);
        rtcOccluded16(valid, m_scene, &context, &ray);
        for (size_t k = 0; k < n; ++k) occluded[first + k] = ray.tfar[k] < 0.0f;
    }
}

}  // namespace relief
