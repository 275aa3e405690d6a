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

void wrappedText(std::string_view text, bool dim = false) {
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * kTextWidthEms);
    if (dim) ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextUnformatted(text.data(), text.data() + text.size());
    if (dim) ImGui::PopStyleColor();
    ImGui::PopTextWrapPos();
}

void tooltip(std::string_view text) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%.*s", int(text.size()), text.data());
}

bool techniqueCombo(ViewerState& state) {
    bool changed = false;
    const std::string current(state.technique->name);
    if (ImGui::BeginCombo("technique", current.c_str())) {
        for (const TechniqueInfo* info : viewableTechniques()) {
            const bool selected = info == state.technique;
            if (ImGui::Selectable(std::string(info->name).c_str(), selected) && !selected) {
                state.technique = info;
                state.params = defaultParams(*info);
                changed = true;
            }
            tooltip(info->summary);
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    wrappedText(
        fmt::format("{}: {}", toString(state.technique->contract), state.technique->summary), true);
    return changed;
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
    for (int k = 0; k < int(std::size(kOverlayNames)); ++k) {
        if (k) ImGui::SameLine();
        changed = ImGui::RadioButton(kOverlayNames[k], &overlay, k) || changed;
    }
    tooltip(
        "shading: Lambert as relief render; steps: iterations per pixel; error: |t - t_exact| "
        "(exact traced too), wrong pixels magenta");
    state.overlay = Overlay(overlay);
    changed = ImGui::Checkbox("shadows", &state.shadows) || changed;
    tooltip("shadow rays traced by the same technique (shading overlay)");
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
    ImGui::Text("%d x %d traced in %.1f ms, hits %.1f %%", info.tracedSize.x, info.tracedSize.y,
                1000.0 * frame.seconds, s.pixels ? 100.0 * double(s.hits) / double(s.pixels) : 0.0);
    ImGui::Text("steps mean %.2f max %.0f, fetches mean %.1f", s.steps.mean, s.steps.max,
                s.fetches.mean);
    if (frame.hasReference)
        ImGui::Text("|t - t_exact| mean %.3g p95 %.3g max %.3g, wrong %.3f %%", s.error.mean,
                    s.error.p95, s.error.max, 100.0 * s.wrongRate());
}

}  // namespace

std::vector<const TechniqueInfo*> viewableTechniques() {
    std::vector<const TechniqueInfo*> list;
    for (const TechniqueInfo& info : techniques())
        if (!info.glsl.empty()) list.push_back(&info);
    return list;
}

ParamValues defaultParams(const TechniqueInfo& info) {
    auto params = resolveParams(info, {});
    RELIEF_CHECK(params);  // the registry's own defaults are valid (registry_test)
    return std::move(*params);
}

PanelActions drawPanel(ViewerState& state, const PanelInfo& info) {
    PanelActions actions;
    ImGui::SetNextWindowPos(ImVec2(8.0f, 8.0f), ImGuiCond_FirstUseEver);
    ImGui::Begin("relief view", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("%.*s  %d x %d, depth %.3g", int(info.source.size()), info.source.data(),
                info.heightfieldSize.x, info.heightfieldSize.y, info.depth);
    wrappedText(info.device, true);
    ImGui::PushItemWidth(ImGui::GetFontSize() * kWidgetWidthEms);
    if (ImGui::CollapsingHeader("technique", ImGuiTreeNodeFlags_DefaultOpen)) {
        actions.rebuildTracer = techniqueCombo(state);
        actions.rebuildTracer = parameterWidgets(state) || actions.rebuildTracer;
    }
    if (ImGui::CollapsingHeader("overlay and light", ImGuiTreeNodeFlags_DefaultOpen))
        actions.redraw = overlayWidgets(state);
    if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen))
        actions.redraw = viewWidgets(state) || actions.redraw;
    ImGui::Separator();
    frameNumbers(info);
    ImGui::PopItemWidth();
    wrappedText(info.status);
    actions.screenshot = ImGui::Button("screenshot (S)");
    ImGui::SameLine();
    ImGui::TextDisabled("drag: orbit, wheel: distance, Esc: quit");
    ImGui::End();
    return actions;
}

}  // namespace relief::viewer
