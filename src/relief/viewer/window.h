#pragma once
// The viewer's window: GLFW with an OpenGL 4.5 core context current on the calling thread, and
// Dear ImGui (its GLFW and OpenGL 3 backends) drawing into it. The context is made through GLX,
// else through EGL on the same display; when neither works, the error names every attempt.
#include <relief/core/error.h>
#include <relief/core/math.h>

#include <memory>
#include <string>

struct GLFWwindow;

namespace relief::viewer {

class Window {
  public:
    // Unsupported when no display can be opened at all, Runtime when one exists but gives no
    // GL 4.5 core context.
    static Result<std::unique_ptr<Window>> open(ivec2 size, const std::string& title);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    // How the context was made ("GLFW window (GLX)"), for gl::EglContext::shareCurrentContext.
    const std::string& contextOrigin() const { return m_contextOrigin; }

    bool shouldClose() const;
    void requestClose();
    // Polls events and starts an ImGui frame.
    void beginFrame();
    // Draws the ImGui frame over whatever was drawn since beginFrame, and presents it.
    void endFrame();
    // endFrame in two halves, for a screenshot of the window with its panel in between.
    void drawUi();
    void present();
    ivec2 framebufferSize() const;
    // True once per press (GLFW_KEY_*), and only while ImGui is not taking the keyboard.
    bool keyPressed(int glfwKey);

  private:
    Window() = default;

    GLFWwindow* m_window = nullptr;
    std::string m_contextOrigin;
    bool m_imguiGlfw = false, m_imguiOpenGl = false;
    bool m_keyDown[512] = {};
};

}  // namespace relief::viewer
