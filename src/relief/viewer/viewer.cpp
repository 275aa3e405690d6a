#include <relief/viewer/viewer.h>

#include <relief/gl/egl_context.h>
#include <relief/gl/gl_tracer.h>
#include <relief/io/image_write.h>
#include <relief/techniques/registry.h>
#include <relief/viewer/image_display.h>
#include <relief/viewer/panel.h>
#include <relief/viewer/window.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <chrono>
#include <cmath>
#include <filesystem>

namespace relief::viewer {

namespace {

constexpr float kDegreesPerPixel = 0.3f;   // mouse drag → orbit angles
constexpr float kZoomPerWheelStep = 0.9f;  // distance factor per wheel notch
constexpr int kMaxScreenshotIndex = 9999;
// While the mouse orbits, frames are traced this much coarser (at least), so the view follows the
// mouse even on a software GL; the full frame follows when the drag ends.
constexpr int kOrbitPixelScale = 4;

// relief-view-001.png, the first that does not exist yet in the working folder.
std::string nextScreenshotPath() {
    for (int k = 1; k < kMaxScreenshotIndex; ++k) {
        std::string path = fmt::format("relief-view-{:03d}.png", k);
        if (!std::filesystem::exists(path)) return path;
    }
    return fmt::format("relief-view-{:03d}.png", kMaxScreenshotIndex);
}

class Viewer {
  public:
    Viewer(const ViewerOptions& options, Window& window)
        : m_options(options), m_window(window), m_renderer(options.surface) {
        m_state.technique = options.technique;
        m_state.params = options.params;
        m_state.overlay = options.overlay;
        m_state.shadows = options.shadows;
        m_state.view = options.view;
        m_state.lightElevationDeg = options.lightElevationDeg;
        m_state.lightAzimuthDeg = options.lightAzimuthDeg;
        m_state.panelCollapsed = options.panelFolded;
        m_state.mesh = options.mesh.has_value();
        m_state.depth = options.surface->depth();
        // Tiling starts on with --tiles or --edge repeat (then once per uv unit, as render --mesh).
        const bool repeat = options.surface->edge() == EdgeMode::Repeat;
        m_state.tiling = options.tiles > 0.0f || repeat;
        if (m_state.tiling) m_state.tiles = options.tiles > 0.0f ? options.tiles : 1.0f;
        m_state.split = options.splitTechnique != nullptr;
        m_state.techniqueB = options.splitTechnique;
        auto device = glBackendDescription();
        m_device = device ? *device : device.error().message;
    }

    Status run() {
        // The command line's techniques must work.
        if (Status s = rebuildTracer(); !s) return s;
        if (m_state.mesh && m_state.split)
            if (Status s = rebuildPreview(1); !s) return s;
        for (int frame = 0;
             !m_window.shouldClose() && (m_options.frames == 0 || frame < m_options.frames);
             ++frame) {
            m_window.beginFrame();
            const bool screenshot = handleKeysAndMouse();
            const PanelActions actions = drawPanel(m_state, panelInfo());
            m_dirty = m_dirty || actions.redraw;
            drawView();
            // Interactive: a failed write is shown in the panel, the viewer goes on.
            if (screenshot || actions.screenshot)
                static_cast<void>(saveScreenshot(nextScreenshotPath()));
            m_window.endFrame();
            // A failure here is shown in the panel, and the previous tracer stays.
            if (actions.rebuildTracer || actions.rebuildMaterial)
                static_cast<void>(rebuildTracer());
            if (m_state.mesh && m_state.split &&
                (actions.rebuildB || actions.rebuildMaterial || !m_meshView.has(1)))
                static_cast<void>(rebuildPreview(1));
        }
        if (m_options.screenshotPath.empty()) return {};
        if (!m_options.screenshotPanel) {
            drawView();  // the last frame again, into the back buffer, without the panel
            return saveScreenshot(m_options.screenshotPath);
        }
        m_window.beginFrame();
        drawPanel(m_state, panelInfo());
        drawView();
        m_window.drawUi();
        const Status saved = saveScreenshot(m_options.screenshotPath);
        m_window.present();
        return saved;
    }

  private:
    // Orbit by mouse, keys; true when a screenshot was asked for.
    bool handleKeysAndMouse() {
        const ImGuiIO& io = ImGui::GetIO();
        OrbitView& view = m_state.view;
        m_orbiting = !io.WantCaptureMouse && ImGui::IsMouseDragging(ImGuiMouseButton_Left);
        if (!io.WantCaptureMouse) {
            if (m_orbiting && (io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f)) {
                view.azimuthDeg =
                    std::remainder(view.azimuthDeg - kDegreesPerPixel * io.MouseDelta.x, 360.0f);
                view.elevationDeg =
                    std::clamp(view.elevationDeg + kDegreesPerPixel * io.MouseDelta.y,
                               -kMaxElevation, kMaxElevation);
                m_dirty = true;
            }
            if (io.MouseWheel != 0.0f) {
                view.distance =
                    std::clamp(view.distance * std::pow(kZoomPerWheelStep, io.MouseWheel),
                               kMinDistance, kMaxDistance);
                m_dirty = true;
            }
        }
        if (m_window.keyPressed(GLFW_KEY_ESCAPE)) m_window.requestClose();
        if (m_window.keyPressed(GLFW_KEY_TAB)) m_state.panelCollapsed = !m_state.panelCollapsed;
        const bool s = m_window.keyPressed(GLFW_KEY_S);
        const bool f12 = m_window.keyPressed(GLFW_KEY_F12);
        return s || f12;
    }

    PanelInfo panelInfo() const {
        const Surface& surface = *m_options.surface;
        PanelInfo info;
        info.source = m_options.sourceName;
        info.heightfieldSize = ivec2(surface.width(), surface.height());
        info.depth = m_state.mesh ? m_state.depth : surface.depth();
        info.device = m_device;
        info.status = m_status;
        info.frame = m_frame ? &*m_frame : nullptr;
        info.tracedSize = m_tracedSize;
        info.mesh = m_options.meshName;
        info.milliseconds[0] = m_meshView.milliseconds(0);
        info.milliseconds[1] = m_meshView.milliseconds(1);
        return info;
    }

    // Builds the tracer of the panel's technique and parameters; on failure the previous one
    // stays, and so do its technique and parameters in the panel.
    Status rebuildTracer() {
        if (m_state.mesh) return rebuildPreview(0);
        const std::string name(m_state.technique->name);
        showMessage(m_state.technique->buildMaps
                        ? fmt::format("building the maps of '{}' ...", name)
                        : fmt::format("compiling '{}' ...", name));
        const auto start = std::chrono::steady_clock::now();
        auto tracer = m_options.makeTracer(*m_state.technique, m_state.params);
        if (!tracer) {
            m_status = fmt::format("'{}' failed: {}", name, tracer.error().message);
            if (m_active.technique) {
                m_state.technique = m_active.technique;
                m_state.params = m_active.params;
            }
            return tracer.error();
        }
        m_tracer = std::move(*tracer);
        m_active = {m_state.technique, m_state.params};
        m_status = fmt::format(
            "'{}' ready in {:.2f} s", name,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        m_dirty = true;
        return {};
    }

    // --mesh: the preview of A (slot 0: the panel's technique and parameters) or B (slot 1: its
    // defaults) on the panel's depth and tiling. On failure the slot keeps its previous preview,
    // and the panel goes back to what that shows.
    Status rebuildPreview(int slot) {
        const TechniqueInfo* technique = slot == 0 ? m_state.technique : m_state.techniqueB;
        const std::string name(technique->name);
        showMessage(fmt::format("building the preview of '{}' ...", name));
        const auto start = std::chrono::steady_clock::now();
        MaterialSpec spec{technique, slot == 0 ? m_state.params : defaultParams(*technique),
                          m_state.depth, m_state.tiling};
        const Status built = m_meshView.build(slot, spec, m_options.makePreview, *m_options.mesh);
        if (!built) {
            m_status = fmt::format("'{}' failed: {}", name, built.error().message);
            const MaterialSpec& last = m_material[slot];
            if (slot == 1 && !last.technique) m_state.split = false;  // nothing to show on B
            if (last.technique) {
                (slot == 0 ? m_state.technique : m_state.techniqueB) = last.technique;
                if (slot == 0) m_state.params = last.params;
                m_state.depth = last.depth;
                m_state.tiling = last.repeat;
            }
            return built;
        }
        m_material[slot] = spec;
        m_status = fmt::format(
            "'{}' ready in {:.2f} s", name,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        return {};
    }

    preview::MeshRenderSettings meshSettings() const {
        preview::MeshRenderSettings settings;
        const ivec2 size = m_window.framebufferSize();
        settings.width = size.x;
        settings.height = size.y;
        settings.view = m_state.view;
        settings.towardsLight =
            directionFromAngles(m_state.lightElevationDeg, m_state.lightAzimuthDeg);
        settings.shadows = m_state.shadows;
        settings.tiles = m_state.tiling ? m_state.tiles : 1.0f;
        settings.specular = Shading{}.specular;  // as relief render --mesh by default
        return settings;
    }

    // What the window shows under the panel: the mesh drawn anew, or the traced image.
    void drawView() {
        if (!m_state.mesh) {
            renderIfNeeded();
            drawImage();
            return;
        }
        const preview::MeshRenderSettings settings = meshSettings();
        if (settings.width < 1 || settings.height < 1) return;  // minimized
        m_meshView.draw(settings, m_state.split, Shading().background);
    }

    // One frame with just `message` over the last image, so that a long build does not look
    // like a hung window.
    void showMessage(const std::string& message) {
        m_window.beginFrame();
        const ImVec2 size = ImGui::GetIO().DisplaySize;
        ImGui::SetNextWindowPos(ImVec2(0.5f * size.x, 0.5f * size.y), ImGuiCond_Always,
                                ImVec2(0.5f, 0.5f));
        ImGui::Begin("##message", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                         ImGuiWindowFlags_NoInputs);
        ImGui::TextUnformatted(message.c_str());
        ImGui::End();
        if (m_state.mesh)
            drawView();
        else
            drawImage();
        m_window.endFrame();
    }

    // The exact tracer for the error overlay, made once; without it the overlay falls back to
    // shading.
    const Tracer* exactTracer() {
        if (m_state.overlay != Overlay::Error) return nullptr;
        if (!m_exact) {
            const TechniqueInfo& exact = referenceTechnique();
            auto tracer = m_options.makeTracer(exact, defaultParams(exact));
            if (!tracer) {
                m_status = "error overlay: " + tracer.error().message;
                m_state.overlay = Overlay::Shading;
                return nullptr;
            }
            m_exact = std::move(*tracer);
        }
        return m_exact.get();
    }

    void renderIfNeeded() {
        const int pixelScale =
            m_orbiting ? std::max(m_state.pixelScale, kOrbitPixelScale) : m_state.pixelScale;
        const ivec2 size = m_window.framebufferSize() / pixelScale;
        if (size.x < 1 || size.y < 1) return;  // minimized
        if (!m_dirty && size == m_tracedSize) return;
        FrameRequest request;
        request.view = m_state.view;
        request.size = size;
        request.shading.towardsLight =
            directionFromAngles(m_state.lightElevationDeg, m_state.lightAzimuthDeg);
        request.shading.shadows = m_state.shadows;
        request.shading.color = m_options.color ? &*m_options.color : nullptr;
        const Tracer* exact = exactTracer();
        request.overlay = m_state.overlay;
        m_frame = m_renderer.render(request, *m_tracer, m_active.technique->name, exact);
        m_display.upload(m_frame->image);
        m_tracedSize = size;
        m_dirty = false;
    }

    void drawImage() { m_display.draw(m_window.framebufferSize(), Shading().background); }

    Status saveScreenshot(const std::string& path) {
        const Status written = writePng(path, ImageDisplay::readBack(m_window.framebufferSize()));
        m_status = written ? "saved " + path : written.error().message;
        return written;
    }

    const ViewerOptions& m_options;
    Window& m_window;
    ViewerState m_state;
    struct Active {  // what m_tracer traces
        const TechniqueInfo* technique = nullptr;
        ParamValues params;
    } m_active;
    ViewRenderer m_renderer;
    ImageDisplay m_display;
    MeshView m_meshView;
    MaterialSpec m_material[2];  // what each slot of m_meshView shows
    std::unique_ptr<Tracer> m_tracer, m_exact;
    std::optional<Frame> m_frame;
    ivec2 m_tracedSize{0, 0};
    bool m_dirty = true;
    bool m_orbiting = false;  // left button dragged on the view
    std::string m_status, m_device;
};

}  // namespace

Status runViewer(const ViewerOptions& options) {
    RELIEF_CHECK(options.surface && options.technique && options.makeTracer);
    RELIEF_CHECK(!options.mesh || options.makePreview);
    auto window = Window::open(options.windowSize, "relief view: " + options.sourceName);
    if (!window) return window.error();
    if (Status s = gl::EglContext::shareCurrentContext((*window)->contextOrigin()); !s) return s;
    Viewer viewer(options, **window);  // destroyed before the window: its GL objects first
    return viewer.run();
}

}  // namespace relief::viewer
