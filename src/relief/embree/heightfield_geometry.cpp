#include <relief/embree/heightfield_geometry.h>

#include <relief/techniques/registry.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace relief::embree {

struct HeightfieldGeometry::State {
    std::shared_ptr<const Surface> surface;
    std::shared_ptr<const Tracer> tracer;
    RTCScene scene = nullptr;
    unsigned geomID = RTC_INVALID_GEOMETRY_ID;
    vec3 lower{0.0f}, upper{0.0f};
};

namespace {

using State = HeightfieldGeometry::State;

// Embree 3 calls with N = 1, 4, 8 or 16; larger N is taken 16 lanes at a time.
constexpr unsigned kLanes = 16;

void bounds(const RTCBoundsFunctionArguments* args) {
    const State& s = *static_cast<const State*>(args->geometryUserPtr);
    RTCBounds& b = *args->bounds_o;
    b.lower_x = s.lower.x, b.lower_y = s.lower.y, b.lower_z = s.lower.z;
    b.upper_x = s.upper.x, b.upper_y = s.upper.y, b.upper_z = s.upper.z;
}

// Traces the valid lanes of `rays` as one batch; calls onHit(lane, t, position) for each hit in
// [tnear, tfar], t in the caller's parametrization (its direction need not be unit length).
template <class OnHit>
void traceLanes(const State& s, const int* valid, RTCRayN* rays, unsigned N, OnHit onHit) {
    for (unsigned first = 0; first < N; first += kLanes) {
        Ray local[kLanes];
        Hit hits[kLanes];
        unsigned lanes[kLanes];
        float nears[kLanes], fars[kLanes], lengths[kLanes];
        unsigned n = 0;
        for (unsigned i = first; i < std::min(N, first + kLanes); ++i) {
            if (valid[i] == 0) continue;
            const vec3 o(RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i));
            const vec3 d(RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i));
            const float near = std::max(0.0f, RTCRayN_tnear(rays, N, i)), far = RTCRayN_tfar(rays, N, i);
            // A unit direction stays as it is (renormalizing would move it by an ulp and the hit of
            // a grazing ray by more than the exact contract's 1e-3).
            float length = glm::length(d);
            if (std::abs(length - 1.0f) <= 4.0f * std::numeric_limits<float>::epsilon()) length = 1.0f;
            if (!(length > 0.0f) || !(near <= far)) continue;  // also an occluded lane (tfar = -inf)
            local[n] = Ray{o + near * d, d / length, (far - near) * length};
            lanes[n] = i, nears[n] = near, fars[n] = far, lengths[n] = length;
            ++n;
        }
        if (n == 0) continue;
        s.tracer->traceBatch(std::span<const Ray>(local, n), std::span<Hit>(hits, n));
        for (unsigned k = 0; k < n; ++k) {
            if (!hits[k].hit) continue;
            const float t = nears[k] + hits[k].t / lengths[k];
            // Tracers clip to [0, tMax]; rounding of the rescaled t must not leave [tnear, tfar].
            if (t < nears[k] || t > fars[k]) continue;
            onHit(lanes[k], t, hits[k].position);
        }
    }
}

void intersect(const RTCIntersectFunctionNArguments* args) {
    const State& s = *static_cast<const State*>(args->geometryUserPtr);
    const unsigned N = args->N;
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
    traceLanes(s, args->valid, rays, N, [&](unsigned i, float t, const vec3& p) {
        const vec3 ng = s.surface->normalAt(p);
        RTCRayN_tfar(rays, N, i) = t;
        RTCHitN_Ng_x(hits, N, i) = ng.x;
        RTCHitN_Ng_y(hits, N, i) = ng.y;
        RTCHitN_Ng_z(hits, N, i) = ng.z;
        RTCHitN_u(hits, N, i) = p.x;
        RTCHitN_v(hits, N, i) = p.y;
        RTCHitN_primID(hits, N, i) = args->primID;
        RTCHitN_geomID(hits, N, i) = args->geomID;
        for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
            RTCHitN_instID(hits, N, i, l) = args->context->instID[l];
    });
}

void occluded(const RTCOccludedFunctionNArguments* args) {
    const State& s = *static_cast<const State*>(args->geometryUserPtr);
    traceLanes(s, args->valid, args->ray, args->N, [&](unsigned i, float, const vec3&) {
        RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    });
}

}  // namespace

HeightfieldGeometry::HeightfieldGeometry(std::unique_ptr<State> state) : m_state(std::move(state)) {}

HeightfieldGeometry::HeightfieldGeometry(HeightfieldGeometry&& other) noexcept = default;

HeightfieldGeometry& HeightfieldGeometry::operator=(HeightfieldGeometry&& other) noexcept {
    if (this != &other) {
        release();
        m_state = std::move(other.m_state);
    }
    return *this;
}

HeightfieldGeometry::~HeightfieldGeometry() { release(); }

void HeightfieldGeometry::release() {
    if (!m_state) return;
    rtcDetachGeometry(m_state->scene, m_state->geomID);
    rtcReleaseScene(m_state->scene);
    m_state.reset();
}

unsigned HeightfieldGeometry::geomID() const { return m_state->geomID; }
const Surface& HeightfieldGeometry::surface() const { return *m_state->surface; }
const Tracer& HeightfieldGeometry::tracer() const { return *m_state->tracer; }

namespace {
Status checkAttachable(RTCScene scene, const Surface* surface) {
    if (!scene) return makeError(ErrorKind::BadArgument, "Embree user geometry: no scene");
    if (!surface) return makeError(ErrorKind::BadArgument, "Embree user geometry: no surface");
    if (surface->edge() != EdgeMode::Clamp)
        return makeError(ErrorKind::Unsupported,
                         "Embree user geometry: only clamp edge mode has finite bounds (repeat tiles forever)");
    return {};
}
}  // namespace

Result<HeightfieldGeometry> attachTracer(RTCScene scene, std::shared_ptr<const Surface> surface,
                                         std::shared_ptr<const Tracer> tracer) {
    if (auto ok = checkAttachable(scene, surface.get()); !ok) return ok.error();
    if (!tracer) return makeError(ErrorKind::BadArgument, "Embree user geometry: no tracer");
    auto state = std::make_unique<State>();
    // Padded outward so that Embree's box test never culls a ray the tracer would hit on a face.
    const vec3 size(float(surface->width()), float(surface->height()), std::max(surface->maxZ(), 1e-3f));
    const float pad = 1e-4f * std::max({size.x, size.y, size.z, 1.0f});
    state->lower = vec3(-pad);
    state->upper = size + vec3(pad);
    state->surface = std::move(surface);
    state->tracer = std::move(tracer);
    RTCDevice device = rtcGetSceneDevice(scene);  // retained: released below
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcReleaseDevice(device);
    if (!geometry) return makeError(ErrorKind::Runtime, "Embree user geometry: rtcNewGeometry failed");
    rtcSetGeometryUserPrimitiveCount(geometry, 1);
    rtcSetGeometryUserData(geometry, state.get());
    rtcSetGeometryBoundsFunction(geometry, bounds, state.get());
    rtcSetGeometryIntersectFunction(geometry, intersect);
    rtcSetGeometryOccludedFunction(geometry, occluded);
    rtcCommitGeometry(geometry);
    state->geomID = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    if (state->geomID == RTC_INVALID_GEOMETRY_ID)
        return makeError(ErrorKind::Runtime, "Embree user geometry: rtcAttachGeometry failed");
    rtcRetainScene(scene);
    state->scene = scene;
    return HeightfieldGeometry(std::move(state));
}

Result<HeightfieldGeometry> attachHeightfield(RTCScene scene, std::shared_ptr<const Surface> surface,
                                              std::string_view technique,
                                              const std::vector<std::pair<std::string, double>>& params,
                                              const MapFile* maps) {
    // Checked before createTracer, which may build maps.
    if (auto ok = checkAttachable(scene, surface.get()); !ok) return ok.error();
    auto tracer = createTracer(technique, surface, params, maps);
    if (!tracer) return tracer.error();
    return attachTracer(scene, std::move(surface), std::shared_ptr<const Tracer>(std::move(*tracer)));
}

}  // namespace relief::embree
