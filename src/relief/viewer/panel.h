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
};

struct PanelActions {
    bool rebuildTracer = false;  // technique or a parameter: maps may depend on them
    bool redraw = false;         // overlay, shadows, light, view or resolution
    bool screenshot = false;
};

// The registry rows the viewer can show: per-pixel techniques with a GLSL tracer.
std::vector<const TechniqueInfo*> viewableTechniques();

// Default parameters of `info` (the registry's, as resolveParams gives them).
ParamValues defaultParams(const TechniqueInfo& info);

PanelActions drawPanel(ViewerState& state, const PanelInfo& info);

}  // namespace relief::viewer
