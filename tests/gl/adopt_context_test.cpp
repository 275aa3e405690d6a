// EglContext::shareCurrentContext (the viewer's window context) is refused once the process has
// settled on another context: tracers made before would otherwise hold GL objects of the old one.
// The success path runs in relief view (viewer_test.cpp).
#include <gtest/gtest.h>
#include <relief/gl/egl_context.h>

namespace relief::gl {
namespace {

TEST(AdoptContext, RefusedOnceTheSharedContextIsSettled) {
    static_cast<void>(EglContext::shared());  // settles it, a context or an error
    const Status adopted = EglContext::shareCurrentContext("test window");
    ASSERT_FALSE(adopted);
    EXPECT_NE(adopted.error().message.find("already settled"), std::string::npos)
        << adopted.error().message;
}

}  // namespace
}  // namespace relief::gl
