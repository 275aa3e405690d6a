#include <relief/viewer/view_renderer.h>

#include <relief/core/check.h>

#include <chrono>

namespace relief::viewer {

namespace {

bool sameView(const OrbitView& a, const OrbitView& b) {
    return a.elevationDeg == b.elevationDeg && a.azimuthDeg == b.azimuthDeg &&
           a.distance == b.distance && a.fovDeg == b.fovDeg;
}

}  // namespace

const Image<Hit>& ViewRenderer::reference(const FrameRequest& request, const Camera& camera,
                                          const Tracer& exact) {
    if (!m_reference || !sameView(m_reference->view, request.view) ||
        m_reference->size != request.size)
        m_reference = Reference{request.view, request.size, tracePrimary(camera, exact)};
    return m_reference->hits;
}

Frame ViewRenderer::render(const FrameRequest& request, const Tracer& tracer, std::string_view name,
                           const Tracer* exact) {
    const auto start = std::chrono::steady_clock::now();
    const Camera camera(request.view, *m_surface, request.size.x, request.size.y);
    Frame frame;
    Image<Hit> hits;
    if (request.overlay == Overlay::Shading) {
        RenderResult shaded = relief::render(*m_surface, camera, tracer, request.shading);
        frame.image = std::move(shaded.color);
        hits = std::move(shaded.hits);
    } else {
        hits = tracePrimary(camera, tracer);
    }
    frame.hasReference = request.overlay == Overlay::Error;
    if (frame.hasReference) {
        RELIEF_CHECK(exact);
        const Image<Hit>& ref = reference(request, camera, *exact);
        frame.stats = compareHits(hits, ref);
        frame.image = errorHeatmap(hits, ref, frame.stats, name);
    } else {
        // Compared with themselves, the hits give their steps and fetches and no error.
        frame.stats = compareHits(hits, hits);
        if (request.overlay == Overlay::Steps) frame.image = stepsHeatmap(hits, frame.stats, name);
    }
    frame.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return frame;
}

}  // namespace relief::viewer
