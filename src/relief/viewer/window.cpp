#include <relief/viewer/window.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdlib>
#include <vector>

namespace relief::viewer {

namespace {

// GLFW reports failures through a callback; the latest one goes into the error we return.
std::string& lastGlfwError() {
    static std::string message;
    return message;
}

void recordGlfwError(int code, const char* description) {
    lastGlfwError() =
        fmt::format("{} (GLFW error 0x{:05X})", description ? description : "?", unsigned(code));
}

std::string takeGlfwError() {
    std::string message = std::exchange(lastGlfwError(), std::string());
    return message.empty() ? "no GLFW error reported" : message;
}

std::string displayDescription() {
    const char* display = std::getenv("DISPLAY");
    return display && *display ? fmt::format("DISPLAY={}", display) : "DISPLAY unset";
}

// The context APIs tried, in order. Debian's GLFW is built for X11, where "native" is GLX.
struct ContextApi {
    const char* name;
    int api;
};
constexpr ContextApi kContextApis[] = {{"GLX", GLFW_NATIVE_CONTEXT_API},
                                       {"EGL", GLFW_EGL_CONTEXT_API}};

GLFWwindow* createWindow(ivec2 size, const std::string& title, const ContextApi& api) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_CREATION_API, api.api);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    return glfwCreateWindow(size.x, size.y, title.c_str(), nullptr, nullptr);
}

}  // namespace

Result<std::unique_ptr<Window>> Window::open(ivec2 size, const std::string& title) {
    glfwSetErrorCallback(recordGlfwError);
    if (!glfwInit())
        return makeError(ErrorKind::Unsupported,
                         "relief view needs a display: GLFW could not open the X11 display ({}): "
                         "{}. Run it in a desktop session or under xvfb-run; images without a "
                         "window come from relief render --backend gl",
                         displayDescription(), takeGlfwError());
    auto window = std::unique_ptr<Window>(new Window());
    std::vector<std::string> tried;
    for (const ContextApi& api : kContextApis) {
        window->m_window = createWindow(size, title, api);
        if (window->m_window) {
            window->m_contextOrigin = fmt::format("GLFW window ({})", api.name);
            break;
        }
        tried.push_back(fmt::format("{}: {}", api.name, takeGlfwError()));
    }
    if (!window->m_window) {
        std::string message =
            fmt::format("no window with an OpenGL 4.5 core context on the display ({}); tried",
                        displayDescription());
        for (const std::string& t : tried) message += "\n  " + t;
        return Error{ErrorKind::Runtime, message};
    }
    glfwMakeContextCurrent(window->m_window);
    glfwSwapInterval(1);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
    ImGui::StyleColorsDark();
    window->m_imguiGlfw = ImGui_ImplGlfw_InitForOpenGL(window->m_window, true);
    window->m_imguiOpenGl = window->m_imguiGlfw && ImGui_ImplOpenGL3_Init("#version 450 core");
    if (!window->m_imguiOpenGl)
        return makeError(ErrorKind::Runtime, "Dear ImGui could not start on the {} context",
                         window->m_contextOrigin);
    return window;
}

Window::~Window() {
    if (m_imguiOpenGl) ImGui_ImplOpenGL3_Shutdown();
    if (m_imguiGlfw) ImGui_ImplGlfw_Shutdown();
    if (ImGui::GetCurrentContext()) ImGui::DestroyContext();
    if (m_window) glfwDestroyWindow(m_window);
    glfwTerminate();
}

bool Window::shouldClose() const { return glfwWindowShouldClose(m_window); }

void Window::requestClose() { glfwSetWindowShouldClose(m_window, GLFW_TRUE); }

void Window::beginFrame() {
    glfwPollEvents();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

void Window::endFrame() {
    drawUi();
    present();
}

void Window::drawUi() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void Window::present() { glfwSwapBuffers(m_window); }

ivec2 Window::framebufferSize() const {
    ivec2 size;
    glfwGetFramebufferSize(m_window, &size.x, &size.y);
    return size;
}

bool Window::keyPressed(int glfwKey) {
    if (glfwKey < 0 || glfwKey >= int(std::size(m_keyDown))) return false;
    const bool down = glfwGetKey(m_window, glfwKey) == GLFW_PRESS;
    const bool pressed = down && !m_keyDown[glfwKey];
    m_keyDown[glfwKey] = down;
    return pressed && !ImGui::GetIO().WantCaptureKeyboard;
}

}  // namespace relief::viewer
