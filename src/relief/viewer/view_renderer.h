#pragma once
// What the viewer shows, as an image: the technique's primary hits shaded as relief render shades
// them (render/renderer.h: Lambert + ambient, optional shadow rays traced by the same tracer),
// or one of render/compare.h's heatmaps (steps; |t - t_exact| against the exact tracer). Knows
// nothing of windows: the tracers passed in decide where rays are traced (the GL backend here).
#include <relief/core/image.h>
#include <relief/render/camera.h>
#include <relief/render/compare.h>
#include <relief/render/renderer.h>

#include <memory>
#include <optional>
#include <string_view>

namespace relief::viewer {

enum class Overlay { Shading, Steps, Error };
inline constexpr const char* kOverlayNames[] = {"shading", "steps", "error"};

struct FrameRequest {
    OrbitView view;
    ivec2 size{1, 1};  // traced pixels
    Overlay overlay = Overlay::Shading;
    Shading shading;
};

struct Frame {
    ImageRgb8 image;
    // Steps and fetches always; the error fields only when compared with exact (hasReference).
    ErrorStats stats;
    bool hasReference = false;
    double seconds = 0.0;  // tracing, shading and the heatmap
};

class ViewRenderer {
  public:
    explicit ViewRenderer(std::shared_ptr<const Surface> surface) : m_surface(std::move(surface)) {}

    // `exact` must be given for the Error overlay (null is fine otherwise); its hits are kept for
    // the next frame with the same view and size, so changing the technique does not retrace them.
    Frame render(const FrameRequest& request, const Tracer& tracer, std::string_view name,
                 const Tracer* exact);

  private:
    const Image<Hit>& reference(const FrameRequest& request, const Camera& camera,
                                const Tracer& exact);

    std::shared_ptr<const Surface> m_surface;
    struct Reference {
        OrbitView view;
        ivec2 size;
        Image<Hit> hits;
    };
    std::optional<Reference> m_reference;
};

}  // namespace relief::viewer
