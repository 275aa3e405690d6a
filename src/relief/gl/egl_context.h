#pragma once
// A headless OpenGL 4.5 core context through EGL, shared by the whole process.
//
// Platforms are tried in order: Mesa's surfaceless platform (llvmpipe or a Mesa GPU driver, no
// window system), then the EGL device platform (eglQueryDevicesEXT, one display per device: a
// headless NVIDIA GPU), then the default display. The first that yields a GL 4.5 core context
// wins; if none does, the error names every attempt with its EGL error code. For debugging,
// RELIEF_EGL_PLATFORM=surfaceless|device|default restricts the search to one platform.
//
// A GL context is current in one thread at a time, and tracers are called from worker threads,
// so every use goes through a Scope: it locks the context's mutex, makes the context current on
// the calling thread and releases it again when the scope ends.
//
// A window (relief view) brings its own context: shareCurrentContext() makes the context current
// on the calling thread the shared one instead, so the tracers draw into the window's GL objects
// and no second context is made current beside it (GLX and EGL contexts do not mix on a thread).
// Scopes on such an adopted context only lock the mutex; they must stay on that thread.
#include <relief/core/error.h>

#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

namespace relief::gl {

class EglContext {
public:
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    // The process-wide context, created on first use. A failure is remembered and returned again
    // (trying every platform once is slow). The error is Unsupported when no EGL display exists at
    // all (tests skip then), Runtime when a display exists but gives no GL 4.5 core context.
    static Result<std::shared_ptr<EglContext>> shared();

    // Adopts the OpenGL 4.5 core context current on this thread (made by a window system, named
    // by `origin`) as the shared context; the caller keeps it alive and current on this thread
    // while GL objects exist. An error when shared() has already settled on a context, or when
    // no GL 4.5 context is current.
    static Status shareCurrentContext(std::string_view origin);

    // Which platform and device won, and GL_VENDOR / GL_RENDERER / GL_VERSION.
    const std::string& description() const { return m_description; }
    bool isSoftware() const { return m_software; }

    class Scope {
    public:
        explicit Scope(const EglContext& context);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

    private:
        const EglContext& m_context;
        std::unique_lock<std::recursive_mutex> m_lock;
        bool m_madeCurrent = false;
    };

    // A new context, not the shared one (tests of the platform search).
    static Result<std::shared_ptr<EglContext>> create();

private:
    EglContext() = default;

    void* m_display = nullptr;  // EGLDisplay
    void* m_context = nullptr;  // EGLContext; null for an adopted context
    bool m_adopted = false;     // shareCurrentContext: current on m_owner, never switched
    std::thread::id m_owner;
    std::string m_description;
    bool m_software = false;
    mutable std::recursive_mutex m_mutex;
    mutable int m_depth = 0;  // nesting of Scopes on the owning thread
};

}  // namespace relief::gl
