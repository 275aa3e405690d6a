#pragma once
// Shared by the GL tests: the skip rule (STYLE: GL tests skip only where no EGL display exists at
// all; where one exists, a context failure is a test failure) and the test surfaces.
#include <relief/core/generators.h>
#include <relief/gl/egl_context.h>
#include <relief/surface/surface.h>

#include <gtest/gtest.h>

#include <memory>
#include <string>

#define RELIEF_REQUIRE_GL()                                                               \
    do {                                                                                  \
        auto glContext_ = ::relief::gl::EglContext::shared();                             \
        if (!glContext_) {                                                                \
            if (glContext_.error().kind == ::relief::ErrorKind::Unsupported)              \
                GTEST_SKIP() << "no EGL display on this machine: "                        \
                             << glContext_.error().message;                               \
            FAIL() << glContext_.error().message;                                         \
        }                                                                                 \
    } while (0)

namespace relief::testing {

inline std::shared_ptr<const Surface> generatedSurface(std::string_view generator, int width,
                                                       int height, float depthRatio,
                                                       EdgeMode edge, uint64_t seed = 1) {
    auto hf = generateHeightfield(generator, width, height, seed);
    if (!hf) {
        ADD_FAILURE() << hf.error().message;
        return nullptr;
    }
    auto field = std::make_shared<const Heightfield>(std::move(*hf));
    return std::make_shared<const Surface>(field, depthRatio * float(std::max(width, height)),
                                           edge);
}

}  // namespace relief::testing
