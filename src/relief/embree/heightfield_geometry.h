#pragma once
// A relief heightfield as an Embree 3 user geometry (RTC_GEOMETRY_TYPE_USER): an Embree renderer
// gets the hits of any registry technique on S (DESIGN §2) without triangulating it. One primitive
// whose bounds are the relief's box; the intersect and occluded callbacks trace the active lanes of
// each call (N = 1, 4, 8 or 16) as one batch through the technique's Tracer (one virtual call per
// callback, none per ray). Space: relief's texel space (DESIGN §1) is the geometry's object space;
// place it in a world with an Embree instance. Clamp edges only (repeat has no finite bounds).
//
// Hits: tfar = t, Ng = Surface::normalAt (the plane that is highest there, or the wall), u, v = the
// hit's texel-space x, y, primID 0. Rays: any direction length (normalized here, t scaled back);
// only hits in [tnear, tfar] count, and the ray is traced from o + tnear·d (a segment starting
// below S is outside DESIGN §3's contract). No intersection filter functions are invoked.
// Threads: Embree calls the callbacks from any number of threads at once; they only read the
// surface and call Tracer::traceBatch, which every registry tracer keeps const and safe to call
// concurrently (traceAll does so from parallel batches; the only shared writes are the safety
// rows' atomic statistics counters).
#include <relief/core/error.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <embree3/rtcore.h>

#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace relief::embree {

// The attached geometry. Embree 3 has no callback when a geometry is freed, so what the callbacks
// read (surface, maps, tracer) lives here: destroying the handle detaches the geometry from its
// scene (commit the scene again before tracing it) and releases the scene it retained.
class HeightfieldGeometry {
public:
    HeightfieldGeometry(HeightfieldGeometry&& other) noexcept;
    HeightfieldGeometry& operator=(HeightfieldGeometry&&) noexcept;
    ~HeightfieldGeometry();

    unsigned geomID() const;
    const Surface& surface() const;
    const Tracer& tracer() const;

    struct State;

private:
    friend Result<HeightfieldGeometry> attachTracer(RTCScene, std::shared_ptr<const Surface>,
                                                    std::shared_ptr<const Tracer>);
    explicit HeightfieldGeometry(std::unique_ptr<State> state);
    void release();
    std::unique_ptr<State> m_state;
};

// Creates the technique's tracer (createTracer: registry name, parameter overrides, baked maps that
// must outlive the handle) and attaches it to `scene` (not committed: the caller commits).
Result<HeightfieldGeometry> attachHeightfield(
    RTCScene scene, std::shared_ptr<const Surface> surface, std::string_view technique = "exact",
    const std::vector<std::pair<std::string, double>>& params = {}, const MapFile* maps = nullptr);

// The same with a tracer the caller already has (made for `surface`; kept alive by the handle).
Result<HeightfieldGeometry> attachTracer(RTCScene scene, std::shared_ptr<const Surface> surface,
                                         std::shared_ptr<const Tracer> tracer);

}  // namespace relief::embree
