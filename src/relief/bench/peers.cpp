#include <relief/bench/peers.h>

#include <relief/bench/timing.h>
#include <relief/core/parallel.h>
#include <relief/embree/embree_scene.h>
#include <relief/gl/camera.h>
#include <relief/gl/gl_tracer.h>

namespace relief::bench {

namespace {

constexpr PeerInfo kPeers[] = {
    {"embree-1", "cpu", PeerKind::Embree1, true},
    {"embree-16", "cpu", PeerKind::Embree16, false},
    {"mesh", "gl", PeerKind::Mesh, true},
};

}  // namespace

std::span<const PeerInfo> peers() { return kPeers; }

std::string userGeometryLabel(std::string_view row, PeerKind kind) {
    RELIEF_CHECK(kind == PeerKind::Embree1 || kind == PeerKind::Embree16);
    return std::string(row) + (kind == PeerKind::Embree1 ? "@user-geometry-1" : "@user-geometry-16");
}

const PeerInfo* summaryPeerOf(std::string_view backend) {
    for (const PeerInfo& p : kPeers)
        if (p.backend == backend && p.summaryPeer) return &p;
    return nullptr;
}

bool isPeer(std::string_view name) {
    for (const PeerInfo& p : kPeers)
        if (p.name == name) return true;
    return false;
}

std::string embreeQuery(PeerKind kind, bool shadow) {
    RELIEF_CHECK(kind == PeerKind::Embree1 || kind == PeerKind::Embree16);
    return std::string(shadow ? "rtcOccluded" : "rtcIntersect") + (kind == PeerKind::Embree16 ? "16" : "1");
}

struct EmbreePeer::Scene {
    std::unique_ptr<EmbreeScene> scene;
};

EmbreePeer::~EmbreePeer() = default;

Result<std::unique_ptr<EmbreePeer>> EmbreePeer::create(const Surface& surface) {
    return build([&] { return EmbreeScene::create(surface); });
}

Result<std::unique_ptr<EmbreePeer>> EmbreePeer::createUserGeometry(std::shared_ptr<const Surface> surface,
                                                                   std::shared_ptr<const Tracer> tracer) {
    return build([&] { return EmbreeScene::createUserGeometry(std::move(surface), std::move(tracer)); });
}

template <class Make>
Result<std::unique_ptr<EmbreePeer>> EmbreePeer::build(Make make) {
    std::unique_ptr<EmbreePeer> peer(new EmbreePeer);
    peer->m_scene = std::make_unique<Scene>();
    const auto start = std::chrono::steady_clock::now();
    auto scene = make();
    if (!scene) return scene.error();
    peer->m_scene->scene = std::move(*scene);
    peer->m_buildSeconds = secondsSince(start);
    return peer;
}

int64_t EmbreePeer::embreeBytes() const { return m_scene->scene->embreeBytes(); }

PeerResult EmbreePeer::run(PeerKind kind, const Camera& camera, int repeats) const {
    RELIEF_CHECK(kind == PeerKind::Embree1 || kind == PeerKind::Embree16);
    const bool packets = kind == PeerKind::Embree16;
    const EmbreeScene& scene = *m_scene->scene;
    // Both kinds, and the CPU rows (runner.cpp), trace the rays in the packets' order.
    const std::vector<size_t> order = packetOrder(camera.width(), camera.height());
    const std::vector<Ray> input = inPacketOrder(primaryRays(camera), order);
    std::vector<Hit> hits(input.size());
    PeerResult result;
    result.seconds = bestOf(repeats, [&] {
        parallelRanges(int64_t(input.size() / 256), 1, [&](int64_t begin, int64_t end) {
            const size_t first = size_t(begin) * 256, count = size_t(end - begin) * 256;
            auto in = std::span(input).subspan(first, count);
            auto out = std::span(hits).subspan(first, count);
            packets ? scene.intersect16(in, out) : scene.intersect1(in, out);
        });
    });
    result.hits = Image<Hit>(camera.width(), camera.height());
    for (size_t k = 0; k < hits.size(); ++k) result.hits.pixels[order[k]] = hits[k];
    return result;
}

OcclusionResult EmbreePeer::occluded(PeerKind kind, std::span<const Ray> rays, int repeats) const {
    RELIEF_CHECK(kind == PeerKind::Embree1 || kind == PeerKind::Embree16);
    const EmbreeScene& scene = *m_scene->scene;
    constexpr size_t kBatch = 256;  // as run(): 16 packets of 16 per parallel task
    OcclusionResult result;
    result.occluded.assign(rays.size(), 0);
    result.seconds = bestOf(repeats, [&] {
        parallelRanges(int64_t((rays.size() + kBatch - 1) / kBatch), 1, [&](int64_t begin, int64_t end) {
            const size_t first = size_t(begin) * kBatch, last = std::min(rays.size(), size_t(end) * kBatch);
            auto in = rays.subspan(first, last - first);
            auto out = std::span(result.occluded).subspan(first, last - first);
            kind == PeerKind::Embree16 ? scene.occluded16(in, out) : scene.occluded1(in, out);
        });
    });
    return result;
}

Result<PeerResult> runMeshPeer(const Surface& surface, const Camera& camera, int frames) {
    auto timing = timeRasterizedMesh(surface, gl::cameraUniforms(camera), {frames, 2});
    if (!timing) return timing.error();
    PeerResult result;
    result.seconds = timing->msPerFrame * 1e-3;
    result.glDevice = timing->device;
    return result;
}

}  // namespace relief::bench
