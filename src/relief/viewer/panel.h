#pragma once
// The viewer's control panel (Dear ImGui): technique and its parameters from the registry row,
// overlay, shadows, light, view and resolution, and the numbers of the last frame.
#include <relief/techniques/technique.h>
#include <relief/viewer/view_renderer.h>

#include <span>
#include <string>
#include <string_view>

namespace relief::viewer {

// Limits of the orbit, shared by the panel's sliders and the mouse.
inline constexpr float kMinDistance = 0.05f;  // box diagonals
inline constexpr float kMaxDistance = 50.0f;
inline constexpr float kMaxElevation = 90.0f;  // degrees, either side of the base plane

// What the panel edits (and the mouse: the view).
struct ViewerState {
    const TechniqueInfo* technique = nullptr;
    ParamValues params;  // complete: every parameter of `technique`
    Overlay overlay = Overlay::Shading;
    bool shadows = false;
    OrbitView view;
    float lightElevationDeg = 45.0f;
    float lightAzimuthDeg = 135.0f;
    int pixelScale = 1;  // one traced pixel covers pixelScale² window pixels
    bool panelCollapsed = false;
    // The material preview (--mesh) only: the relief's depth, tiling (repeat edges and `tiles`
    // repeats per uv unit), and the A/B split with `techniqueB` (its default parameters) on the
    // right half.
    bool mesh = false;
    float depth = 0.0f;
    bool tiling = false;
    float tiles = 2.0f;
    bool split = false;
    const TechniqueInfo* techniqueB = nullptr;
};

// What the panel shows and does not edit.
struct PanelInfo {
    std::string_view source;  // the heightfield's name
    ivec2 heightfieldSize{0, 0};
    float depth = 0.0f;
    std::string_view device;  // the GL context
    std::string_view status;  // the last build, error or screenshot
    const Frame* frame = nullptr;
    ivec2 tracedSize{0, 0};
    std::string_view mesh;                // --mesh as given
    double milliseconds[2] = {0.0, 0.0};  // --mesh: the last draw of A and of B
};

struct PanelActions {
    bool rebuildTracer = false;  // technique or a parameter: maps may depend on them
    bool redraw = false;         // overlay, shadows, light, view or resolution
    bool screenshot = false;
    bool rebuildB = false;         // --mesh: technique B
    bool rebuildMaterial = false;  // --mesh: depth or tiling: the surface changes, so A and B
};

// The panel's width is at most this fraction of the window's (less its margin).
inline constexpr float kMaxPanelFraction = 1.0f / 3.0f;

// The registry rows the viewer can show: per-pixel techniques with a GLSL tracer, or with --mesh
// the rows with a shader-library function.
std::vector<const TechniqueInfo*> viewableTechniques(bool mesh = false);

// Default parameters of `info` (the registry's, as resolveParams gives them).
ParamValues defaultParams(const TechniqueInfo& info);

PanelActions drawPanel(ViewerState& state, const PanelInfo& info);

}  // namespace relief::viewer
