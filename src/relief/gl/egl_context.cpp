#include <relief/gl/egl_context.h>

#include <relief/core/check.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdlib>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

namespace relief::gl {

namespace {

// llvmpipe is faster with a few more threads than cores (compute and rasterizer bins).
constexpr unsigned kLlvmpipeExtraThreads = 1;
constexpr int kMaxDevices = 16;

std::string eglErrorName(EGLint code) {
    switch (code) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
        default: return "unknown";
    }
}

std::string lastEglError() {
    const EGLint code = eglGetError();
    return fmt::format("{} 0x{:04X}", eglErrorName(code), unsigned(code));
}

bool hasExtension(const char* list, std::string_view name) {
    if (!list) return false;
    std::string_view rest(list);
    while (!rest.empty()) {
        const size_t space = rest.find(' ');
        if (rest.substr(0, space) == name) return true;
        if (space == std::string_view::npos) break;
        rest.remove_prefix(space + 1);
    }
    return false;
}

void raiseLlvmpipeThreads() {
    if (std::getenv("LP_NUM_THREADS")) return;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    ::setenv("LP_NUM_THREADS", std::to_string(cores + kLlvmpipeExtraThreads).c_str(), 0);
}

struct Attempt {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string failure;       // empty on success
    bool initialized = false;  // eglInitialize succeeded (a display exists)
};

// Initializes `display`, creates a GL 4.5 core context and makes it current without a surface.
Attempt tryDisplay(EGLDisplay display) {
    Attempt a;
    if (display == EGL_NO_DISPLAY) {
        a.failure = "no display (" + lastEglError() + ")";
        return a;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        a.failure = "eglInitialize failed (" + lastEglError() + ")";
        return a;
    }
    a.initialized = true;
    auto fail = [&](std::string what) {
        a.failure = std::move(what);
        eglTerminate(display);
        return a;
    };
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context"))
        return fail(fmt::format("EGL {}.{} without EGL_KHR_surfaceless_context", major, minor));
    if (!eglBindAPI(EGL_OPENGL_API))
        return fail("eglBindAPI(EGL_OPENGL_API) failed (" + lastEglError() + ")");
    EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
    if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
        const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                        EGL_PBUFFER_BIT, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count < 1)
            return fail("no EGL config with EGL_OPENGL_BIT (" + lastEglError() + ")");
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4,
                                     EGL_CONTEXT_MINOR_VERSION, 5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (context == EGL_NO_CONTEXT)
        return fail("eglCreateContext(OpenGL 4.5 core) failed (" + lastEglError() + ")");
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        std::string error = lastEglError();
        eglDestroyContext(display, context);
        return fail("eglMakeCurrent without a surface failed (" + error + ")");
    }
    if (epoxy_gl_version() < 45) {
        const int version = epoxy_gl_version();
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
        return fail(fmt::format("context reports OpenGL {}.{}, need 4.5", version / 10,
                                version % 10));
    }
    a.display = display;
    a.context = context;
    return a;
}

std::string glString(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? reinterpret_cast<const char*>(s) : "?";
}

struct CurrentContextInfo {
    std::string description;  // "ORIGIN: vendor / renderer / OpenGL version"
    bool software = false;    // llvmpipe or softpipe
};

CurrentContextInfo describeCurrentContext(std::string_view origin) {
    const std::string renderer = glString(GL_RENDERER);
    return {fmt::format("{}: {} / {} / OpenGL {}", origin, glString(GL_VENDOR), renderer,
                        glString(GL_VERSION)),
            renderer.find("llvmpipe") != std::string::npos ||
                renderer.find("softpipe") != std::string::npos};
}

}  // namespace

Result<std::shared_ptr<EglContext>> EglContext::create() {
    raiseLlvmpipeThreads();
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool platformBase = hasExtension(clientExtensions, "EGL_EXT_platform_base");
    std::vector<std::string> tried;
    bool anyDisplay = false;
    Attempt won;
    std::string platform;
    bool softwareDevice = false;

    // RELIEF_EGL_PLATFORM=surfaceless|device|default tries only that platform (debugging).
    const char* only = std::getenv("RELIEF_EGL_PLATFORM");
    auto wanted = [&](std::string_view platformName) {
        if (!only || !*only || platformName == only) return true;
        tried.push_back(fmt::format("{}: skipped (RELIEF_EGL_PLATFORM={})", platformName, only));
        return false;
    };

    // 1. Mesa's surfaceless platform.
    if (wanted("surfaceless")) {
        if (!platformBase || !hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
            tried.push_back("surfaceless: EGL_MESA_platform_surfaceless not offered");
        } else {
            Attempt a = tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                            EGL_DEFAULT_DISPLAY, nullptr));
            if (a.failure.empty()) {
                won = a;
                platform = "EGL_PLATFORM_SURFACELESS_MESA";
            } else {
                tried.push_back("surfaceless: " + a.failure);
                anyDisplay = anyDisplay || a.initialized;
            }
        }
    }

    // 2. The device platform, one display per device (headless NVIDIA).
    if (!won.context && wanted("device")) {
        // EGL_EXT_device_base is device_enumeration + device_query (NVIDIA offers only it).
        const bool enumeration =
            hasExtension(clientExtensions, "EGL_EXT_device_enumeration") ||
            hasExtension(clientExtensions, "EGL_EXT_device_base");
        if (!platformBase || !enumeration ||
            !hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
            tried.push_back(fmt::format("device: EGL_EXT_device_enumeration (or _base) and "
                                        "EGL_EXT_platform_device not both offered (client "
                                        "extensions: {})",
                                        clientExtensions ? clientExtensions : "none"));
        } else {
            EGLDeviceEXT devices[kMaxDevices];
            EGLint count = 0;
            if (!eglQueryDevicesEXT(kMaxDevices, devices, &count)) {
                tried.push_back("device: eglQueryDevicesEXT failed (" + lastEglError() + ")");
            } else if (count == 0) {
                tried.push_back("device: no EGL devices");
            }
            for (EGLint k = 0; k < count && !won.context; ++k) {
                const char* deviceExtensions = eglQueryDeviceStringEXT(devices[k], EGL_EXTENSIONS);
                std::string name = fmt::format("device {}", k);
                if (hasExtension(deviceExtensions, "EGL_EXT_device_drm")) {
                    const char* file = eglQueryDeviceStringEXT(devices[k], EGL_DRM_DEVICE_FILE_EXT);
                    if (file) name += fmt::format(" ({})", file);
                }
                Attempt a = tryDisplay(
                    eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[k], nullptr));
                if (a.failure.empty()) {
                    won = a;
                    platform = "EGL_PLATFORM_DEVICE_EXT " + name;
                    softwareDevice = hasExtension(deviceExtensions, "EGL_MESA_device_software");
                } else {
                    tried.push_back(name + ": " + a.failure);
                    anyDisplay = anyDisplay || a.initialized;
                }
            }
        }
    }

    // 3. Whatever the default display is.
    if (!won.context && wanted("default")) {
        Attempt a = tryDisplay(eglGetDisplay(EGL_DEFAULT_DISPLAY));
        if (a.failure.empty()) {
            won = a;
            platform = "eglGetDisplay(EGL_DEFAULT_DISPLAY)";
        } else {
            tried.push_back("default display: " + a.failure);
            anyDisplay = anyDisplay || a.initialized;
        }
    }

    if (!won.context) {
        std::string message = anyDisplay
                                  ? "no headless OpenGL 4.5 core context through EGL; tried"
                                  : "no EGL display could be initialized; tried";
        for (const std::string& t : tried) message += "\n  " + t;
        // Unsupported: this machine has no EGL display at all; Runtime: one exists but failed.
        return Error{anyDisplay ? ErrorKind::Runtime : ErrorKind::Unsupported, message};
    }

    auto context = std::shared_ptr<EglContext>(new EglContext());
    context->m_display = won.display;
    context->m_context = won.context;
    const CurrentContextInfo info = describeCurrentContext(platform);
    context->m_software = softwareDevice || info.software;
    context->m_description = info.description;
    eglMakeCurrent(won.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    return context;
}

namespace {

// The process-wide context (or the error of making it), settled once: by the first shared() or
// by shareCurrentContext().
struct SharedSlot {
    std::mutex mutex;
    std::optional<Result<std::shared_ptr<EglContext>>> context;
};

SharedSlot& sharedSlot() {
    // Never destroyed: drivers may already be unloading when static destructors run.
    static auto* slot = new SharedSlot();
    return *slot;
}

}  // namespace

Result<std::shared_ptr<EglContext>> EglContext::shared() {
    SharedSlot& slot = sharedSlot();
    std::lock_guard lock(slot.mutex);
    if (!slot.context.has_value()) slot.context.emplace(create());
    return *slot.context;
}

Status EglContext::shareCurrentContext(std::string_view origin) {
    SharedSlot& slot = sharedSlot();
    std::lock_guard lock(slot.mutex);
    if (slot.context.has_value())
        return makeError(ErrorKind::Runtime, "GL backend: cannot adopt the {} context: the "
                         "process already settled on another one", origin);
    if (epoxy_gl_version() < 45)
        return makeError(ErrorKind::Runtime, "GL backend: the {} context reports OpenGL {}.{}, "
                         "need 4.5", origin, epoxy_gl_version() / 10, epoxy_gl_version() % 10);
    auto context = std::shared_ptr<EglContext>(new EglContext());
    context->m_adopted = true;
    context->m_owner = std::this_thread::get_id();
    const CurrentContextInfo info = describeCurrentContext(origin);
    context->m_software = info.software;
    context->m_description = info.description;
    slot.context.emplace(std::move(context));
    return {};
}

// The display is not terminated: EGL hands every caller the same display for a platform, and
// terminating it would end other contexts on it.
EglContext::~EglContext() {
    if (m_context) eglDestroyContext(m_display, m_context);
}

EglContext::Scope::Scope(const EglContext& context) : m_context(context), m_lock(context.m_mutex) {
    if (m_context.m_adopted) {
        // A window's context cannot be made current here; it must already be, on its thread.
        RELIEF_CHECK(std::this_thread::get_id() == m_context.m_owner);
        ++m_context.m_depth;
        return;
    }
    if (m_context.m_depth++ == 0) {
        const bool ok = eglMakeCurrent(m_context.m_display, EGL_NO_SURFACE, EGL_NO_SURFACE,
                                       m_context.m_context);
        RELIEF_CHECK(ok);
        m_madeCurrent = true;
    }
}

EglContext::Scope::~Scope() {
    if (--m_context.m_depth == 0 && m_madeCurrent)
        eglMakeCurrent(m_context.m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

}  // namespace relief::gl
