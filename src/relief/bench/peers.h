#pragma once
// The peers every technique is measured against in the same run (DESIGN §8): Embree on the same
// triangles (rtcIntersect1, rtcIntersect16 on 4×4 packets) on the CPU, the rasterized mesh on GL.
#include <relief/core/error.h>
#include <relief/core/image.h>
#include <relief/render/camera.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace relief::bench {

enum class PeerKind : uint8_t { Embree1, Embree16, Mesh };

struct PeerInfo {
    std::string_view name;
    std::string_view backend;  // "cpu" or "gl"
    PeerKind kind;
    bool summaryPeer;  // the one the summary's "× peer" divides by on its backend
};

std::span<const PeerInfo> peers();
// A row's label behind an Embree user geometry, traced like peer `kind` (Embree1 or Embree16):
// "exact@user-geometry-16".
std::string userGeometryLabel(std::string_view row, PeerKind kind);
// The peer the summary compares rows of `backend` with, or null.
const PeerInfo* summaryPeerOf(std::string_view backend);
bool isPeer(std::string_view name);
// The Embree call an Embree peer (Embree1, Embree16) times: rtcIntersect1/16 on primary rays,
// rtcOccluded1/16 on shadow rays.
std::string embreeQuery(PeerKind kind, bool shadow);

// One timed run of a peer over the camera's primary rays (CPU) or frame (GL).
struct PeerResult {
    Image<Hit> hits;       // empty for the mesh (it draws, it does not report hits)
    double seconds = 0;    // best of the repeats; ms per frame / 1000 for GL
    std::string glDevice;  // GL only
};

struct OcclusionResult {
    std::vector<uint8_t> occluded;
    double seconds = 0;
};

// The Embree scene of a surface, built once per heightfield (clamp edges only): its triangles, or
// the heightfield as a user geometry over a row's tracer (BenchConfig::userGeometry).
class EmbreePeer {
public:
    static Result<std::unique_ptr<EmbreePeer>> create(const Surface& surface);
    static Result<std::unique_ptr<EmbreePeer>> createUserGeometry(std::shared_ptr<const Surface> surface,
                                                                  std::shared_ptr<const Tracer> tracer);
    ~EmbreePeer();
    double buildSeconds() const { return m_buildSeconds; }
    // Bytes Embree's device holds for the scene (BVH, buffers), counted by its memory monitor.
    int64_t embreeBytes() const;
    PeerResult run(PeerKind kind, const Camera& camera, int repeats) const;
    // Occlusion queries (rtcOccluded1 for Embree1, rtcOccluded16 on consecutive groups of 16 for
    // Embree16) on `rays` as given, each on [0, tMax]: occluded flags, best of the repeats.
    OcclusionResult occluded(PeerKind kind, std::span<const Ray> rays, int repeats) const;

private:
    EmbreePeer() = default;
    template <class Make>
    static Result<std::unique_ptr<EmbreePeer>> build(Make make);
    struct Scene;
    std::unique_ptr<Scene> m_scene;
    double m_buildSeconds = 0;
};

// The rasterized mesh: ms per frame with glFinish, `frames` timed frames.
Result<PeerResult> runMeshPeer(const Surface& surface, const Camera& camera, int frames);

}  // namespace relief::bench
