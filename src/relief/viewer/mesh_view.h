#pragma once
// relief view --mesh: the material preview (preview/mesh_renderer.h) drawn straight into the
// window, one MeshPreview per technique shown; with a split, technique A fills the left half and
// B the right half of the same view (a scissor each), and each draw is timed on its own.
#include <relief/core/error.h>
#include <relief/preview/mesh_renderer.h>
#include <relief/techniques/technique.h>

#include <functional>
#include <optional>

namespace relief::viewer {

// What a MeshPreview is made for: the row, its (complete) parameters, and the surface they are
// built on (the depth slider and the tiling toggle change its depth and edge mode).
struct MaterialSpec {
    const TechniqueInfo* technique = nullptr;
    ParamValues params;
    float depth = 0.0f;
    bool repeat = false;  // EdgeMode::Repeat, else Clamp
};

// Makes the preview of a spec with the window's context current. The CLI passes one that builds
// the maps (or reads --maps) exactly as relief render --mesh does.
using PreviewFactory = std::function<Result<preview::MeshPreview>(const MaterialSpec&)>;

class MeshView {
  public:
    // Builds the preview for `spec` in slot 0 (A) or 1 (B); on failure the slot keeps its
    // previous preview.
    Status build(int slot, const MaterialSpec& spec, const PreviewFactory& factory,
                 const preview::Mesh& mesh);
    bool has(int slot) const { return m_slots[slot].preview.has_value(); }

    // Clears the framebuffer and draws A (whole window, or the left half with `split`) and B
    // (the right half). The settings' size is the framebuffer's.
    void draw(const preview::MeshRenderSettings& settings, bool split, const vec3& background);
    // Milliseconds of the last draw of a slot (GPU work included: it waits for it).
    double milliseconds(int slot) const { return m_slots[slot].milliseconds; }

  private:
    struct Slot {
        std::optional<preview::MeshPreview> preview;
        double milliseconds = 0.0;
    };
    Slot m_slots[2];
};

}  // namespace relief::viewer
