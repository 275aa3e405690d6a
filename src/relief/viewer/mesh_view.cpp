#include <relief/viewer/mesh_view.h>

#include <relief/gl/program.h>

#include <chrono>

namespace relief::viewer {

namespace {

constexpr int kSplitLineWidth = 2;  // pixels between the halves
constexpr float kSplitLine[4] = {0.9f, 0.9f, 0.9f, 1.0f};

}  // namespace

Status MeshView::build(int slot, const MaterialSpec& spec, const PreviewFactory& factory,
                       const preview::Mesh& mesh) {
    auto made = factory(spec);
    if (!made) return made.error();
    made->setMesh(mesh);
    m_slots[slot].preview = std::move(*made);
    return {};
}

void MeshView::draw(const preview::MeshRenderSettings& settings, bool split,
                    const vec3& background) {
    const int w = settings.width, h = settings.height;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w, h);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(background.x, background.y, background.z, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const Camera camera = preview::meshCamera(settings);
    split = split && has(1);
    const int half = w / 2;
    // Left edge and width of each slot's part of the window.
    const ivec2 parts[2] = {split ? ivec2(0, half) : ivec2(0, w), ivec2(half, w - half)};
    for (int slot = 0; slot < (split ? 2 : 1); ++slot) {
        if (!has(slot)) continue;
        glEnable(GL_SCISSOR_TEST);
        glScissor(parts[slot].x, 0, parts[slot].y, h);
        glFinish();  // time this draw alone
        const auto start = std::chrono::steady_clock::now();
        m_slots[slot].preview->draw(camera, settings);
        glFinish();
        m_slots[slot].milliseconds =
            1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (split) {
        glScissor(half - kSplitLineWidth / 2, 0, kSplitLineWidth, h);
        glClearBufferfv(GL_COLOR, 0, kSplitLine);
    }
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
}

}  // namespace relief::viewer
