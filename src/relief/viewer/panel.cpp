#include <relief/viewer/panel.h>

#include <relief/core/check.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace relief::viewer {

namespace {

// Parameters with a wider range get a typed field: a slider over 0..1e9 cannot pick 12.
constexpr double kMaxSliderRange = 1000.0;
constexpr int kPixelScales[] = {1, 2, 4};
constexpr const char* kPixelScaleNames[] = {"full", "1/2", "1/4"};
constexpr float kTextWidthEms = 28.0f;  // long lines (device, map errors) wrap here
constexpr float kWidgetWidthEms = 14.0f;
constexpr float kPanelMargin = 8.0f;     // pixels between the panel and the window's edges
constexpr float kMinDepthRatio = 1e-3f;  // the depth slider: this to kMaxDepthRatio × the width
constexpr float kMaxDepthRatio = 0.5f;

// Where text wraps, in the panel's coordinates: kTextWidthEms, or less in a narrow window.
float g_wrapWidth = 0.0f;

void wrappedText(std::string_view text, bool dim = false) {
    ImGui::PushTextWrapPos(g_wrapWidth);
    if (dim) ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextUnformatted(text.data(), text.data() + text.size());
    if (dim) ImGui::PopStyleColor();
    ImGui::PopTextWrapPos();
}

void tooltip(std::string_view text) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%.*s", int(text.size()), text.data());
}

// True when `technique` was set to another row.
bool rowCombo(const char* label, const TechniqueInfo*& technique, bool mesh) {
    bool changed = false;
    const std::string current(technique->name);
    if (ImGui::BeginCombo(label, current.c_str())) {
        for (const TechniqueInfo* info : viewableTechniques(mesh)) {
            const bool selected = info == technique;
            if (ImGui::Selectable(std::string(info->name).c_str(), selected) && !selected) {
                technique = info;
                changed = true;
            }
            tooltip(info->summary);
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    return changed;
}

bool techniqueCombo(ViewerState& state) {
    const bool changed =
        rowCombo(state.mesh ? "technique A" : "technique", state.technique, state.mesh);
    if (changed) state.params = defaultParams(*state.technique);
    wrappedText(
        fmt::format("{}: {}", toString(state.technique->contract), state.technique->summary), true);
    return changed;
}

// --mesh: depth, tiling and the split; `actions` says what must be rebuilt.
void materialWidgets(ViewerState& state, const PanelInfo& info, PanelActions& actions) {
    const float width = float(info.heightfieldSize.x);
    // A deeper --depth than the range stays reachable.
    const float maxDepth = std::max(kMaxDepthRatio * width, state.depth);
    ImGui::SliderFloat("depth", &state.depth, kMinDepthRatio * width, maxDepth, "%.3g texels",
                       ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic);
    tooltip("the relief's depth D in texels (maps are rebuilt when the slider is released)");
    actions.rebuildMaterial = ImGui::IsItemDeactivatedAfterEdit();
    actions.rebuildMaterial = ImGui::Checkbox("tiling", &state.tiling) || actions.rebuildMaterial;
    tooltip("repeat the maps (edge mode repeat) and tile them across each face");
    if (state.tiling)
        actions.redraw =
            ImGui::SliderFloat("tiles", &state.tiles, 1.0f, 16.0f, "%.1f per uv") || actions.redraw;
    actions.redraw = ImGui::Checkbox("A/B split", &state.split) || actions.redraw;
    tooltip("technique A on the left half, B on the right, each timed");
    if (state.split && !state.techniqueB) state.techniqueB = state.technique;
    if (state.split) actions.rebuildB = rowCombo("technique B", state.techniqueB, true);
}

// True when an edit is finished (slider released, Enter, a step button): the maps may depend on
// the value, so the tracer is rebuilt then and not on every step of a drag.
bool parameterWidget(const ParamSpec& spec, double& value) {
    const std::string label(spec.name);
    const char* format = spec.integer ? "%.0f" : "%.4g";
    bool finished = false;
    if (spec.maxValue - spec.minValue > kMaxSliderRange) {
        const double step = 1.0;
        finished = ImGui::InputScalar(label.c_str(), ImGuiDataType_Double, &value,
                                      spec.integer ? &step : nullptr, nullptr, format,
                                      ImGuiInputTextFlags_EnterReturnsTrue);
    } else {
        ImGui::SliderScalar(label.c_str(), ImGuiDataType_Double, &value, &spec.minValue,
                            &spec.maxValue, format, ImGuiSliderFlags_AlwaysClamp);
    }
    finished = finished || ImGui::IsItemDeactivatedAfterEdit();
    tooltip(spec.help);
    value = std::clamp(spec.integer ? std::round(value) : value, spec.minValue, spec.maxValue);
    return finished;
}

bool parameterWidgets(ViewerState& state) {
    bool finished = false;
    for (const ParamSpec& spec : state.technique->params) {
        double value = state.params.get(spec.name);
        finished = parameterWidget(spec, value) || finished;
        state.params.set(std::string(spec.name), value);
    }
    if (state.technique->params.empty()) ImGui::TextDisabled("no parameters");
    return finished;
}

bool overlayWidgets(ViewerState& state) {
    int overlay = int(state.overlay);
    bool changed = false;
    for (int k = 0; k < int(std::size(kOverlayNames)) && !state.mesh; ++k) {
        if (k) ImGui::SameLine();
        changed = ImGui::RadioButton(kOverlayNames[k], &overlay, k) || changed;
    }
    if (!state.mesh)
        tooltip(
            "shading: Lambert as relief render; steps: iterations per pixel; error: |t - t_exact| "
            "(exact traced too), wrong pixels magenta");
    state.overlay = Overlay(overlay);
    changed = ImGui::Checkbox("shadows", &state.shadows) || changed;
    tooltip(state.mesh ? "self-shadows: the row's shadow function toward the light"
                       : "shadow rays traced by the same technique (shading overlay)");
    changed =
        ImGui::SliderFloat("light elevation", &state.lightElevationDeg, 0.0f, 90.0f, "%.1f deg") ||
        changed;
    changed =
        ImGui::SliderFloat("light azimuth", &state.lightAzimuthDeg, -180.0f, 180.0f, "%.1f deg") ||
        changed;
    return changed;
}

bool viewWidgets(ViewerState& state) {
    OrbitView& view = state.view;
    bool changed = false;
    changed = ImGui::SliderFloat("elevation", &view.elevationDeg, -kMaxElevation, kMaxElevation,
                                 "%.1f deg") ||
              changed;
    changed =
        ImGui::SliderFloat("azimuth", &view.azimuthDeg, -180.0f, 180.0f, "%.1f deg") || changed;
    changed = ImGui::SliderFloat("distance", &view.distance, kMinDistance, kMaxDistance, "%.2f",
                                 ImGuiSliderFlags_Logarithmic) ||
              changed;
    tooltip("in box diagonals");
    changed = ImGui::SliderFloat("fov", &view.fovDeg, 5.0f, 120.0f, "%.0f deg") || changed;
    if (state.mesh) return changed;  // drawn at the window's resolution
    const auto scale =
        std::find(std::begin(kPixelScales), std::end(kPixelScales), state.pixelScale);
    int scaleIndex = scale == std::end(kPixelScales) ? 0 : int(scale - std::begin(kPixelScales));
    if (ImGui::Combo("resolution", &scaleIndex, kPixelScaleNames,
                     int(std::size(kPixelScaleNames)))) {
        state.pixelScale = kPixelScales[scaleIndex];
        changed = true;
    }
    tooltip("traced pixels: lower is faster while moving");
    return changed;
}

void frameNumbers(const PanelInfo& info) {
    if (!info.frame) {
        ImGui::TextDisabled("no frame yet");
        return;
    }
    const Frame& frame = *info.frame;
    const ErrorStats& s = frame.stats;
    ImGui::TextWrapped("%d x %d traced in %.1f ms, hits %.1f %%", info.tracedSize.x,
                       info.tracedSize.y, 1000.0 * frame.seconds,
                       s.pixels ? 100.0 * double(s.hits) / double(s.pixels) : 0.0);
    ImGui::TextWrapped("steps mean %.2f max %.0f, fetches mean %.1f", s.steps.mean, s.steps.max,
                       s.fetches.mean);
    if (frame.hasReference)
        ImGui::TextWrapped("|t - t_exact| mean %.3g p95 %.3g max %.3g, wrong %.3f %%", s.error.mean,
                           s.error.p95, s.error.max, 100.0 * s.wrongRate());
}

void meshNumbers(const ViewerState& state, const PanelInfo& info) {
    ImGui::TextWrapped("A %.*s: %.2f ms", int(state.technique->name.size()),
                       state.technique->name.data(), info.milliseconds[0]);
    if (state.split && state.techniqueB)
        ImGui::TextWrapped("B %.*s: %.2f ms", int(state.techniqueB->name.size()),
                           state.techniqueB->name.data(), info.milliseconds[1]);
}

}  // namespace

std::vector<const TechniqueInfo*> viewableTechniques(bool mesh) {
    std::vector<const TechniqueInfo*> list;
    for (const TechniqueInfo& info : techniques())
        if (mesh ? !info.shaderFunction.empty() : !info.glsl.empty()) list.push_back(&info);
    return list;
}

ParamValues defaultParams(const TechniqueInfo& info) {
    auto params = resolveParams(info, {});
    RELIEF_CHECK(params);  // the registry's own defaults are valid (registry_test)
    return std::move(*params);
}

PanelActions drawPanel(ViewerState& state, const PanelInfo& info) {
    PanelActions actions;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float maxWidth = std::max(1.0f, kMaxPanelFraction * display.x - kPanelMargin);
    g_wrapWidth = std::min(ImGui::GetFontSize() * kTextWidthEms,
                           maxWidth - 2.0f * ImGui::GetStyle().WindowPadding.x);
    ImGui::SetNextWindowPos(ImVec2(kPanelMargin, kPanelMargin), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSizeConstraints(
        ImVec2(0.0f, 0.0f), ImVec2(maxWidth, std::max(1.0f, display.y - 2.0f * kPanelMargin)));
    ImGui::SetNextWindowCollapsed(state.panelCollapsed, ImGuiCond_Always);
    const bool open = ImGui::Begin("relief view (Tab)", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    state.panelCollapsed = ImGui::IsWindowCollapsed();  // the title bar's arrow toggles it too
    if (!open) {
        ImGui::End();
        return actions;
    }
    ImGui::TextWrapped("%.*s  %d x %d, depth %.3g", int(info.source.size()), info.source.data(),
                       info.heightfieldSize.x, info.heightfieldSize.y, info.depth);
    if (state.mesh) ImGui::TextWrapped("on mesh %.*s", int(info.mesh.size()), info.mesh.data());
    wrappedText(info.device, true);
    ImGui::PushItemWidth(std::min(ImGui::GetFontSize() * kWidgetWidthEms, 0.5f * maxWidth));
    if (ImGui::CollapsingHeader("technique", ImGuiTreeNodeFlags_DefaultOpen)) {
        actions.rebuildTracer = techniqueCombo(state);
        actions.rebuildTracer = parameterWidgets(state) || actions.rebuildTracer;
    }
    if (state.mesh && ImGui::CollapsingHeader("material", ImGuiTreeNodeFlags_DefaultOpen))
        materialWidgets(state, info, actions);
    if (ImGui::CollapsingHeader(state.mesh ? "light" : "overlay and light",
                                ImGuiTreeNodeFlags_DefaultOpen))
        actions.redraw = overlayWidgets(state) || actions.redraw;
    if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen))
        actions.redraw = viewWidgets(state) || actions.redraw;
    ImGui::Separator();
    if (state.mesh)
        meshNumbers(state, info);
    else
        frameNumbers(info);
    ImGui::PopItemWidth();
    wrappedText(info.status);
    actions.screenshot = ImGui::Button("screenshot (S)");
    wrappedText("drag: orbit, wheel: distance, Tab: panel, Esc: quit", true);
    ImGui::End();
    return actions;
}

}  // namespace relief::viewer
