#pragma once
// Puts the viewer's image on the window: an RGB8 texture, blitted into the default framebuffer
// scaled to fit with its aspect kept (letterboxed on the background colour) and flipped, since the
// image has row 0 at the top and GL at the bottom. No shader: a framebuffer blit does it all.
// Needs the window's context current; GL objects live as long as the display.
#include <relief/core/image.h>
#include <relief/core/math.h>
#include <relief/gl/program.h>

namespace relief::viewer {

class ImageDisplay {
  public:
    ImageDisplay();
    void upload(const ImageRgb8& image);
    // Clears the framebuffer to `background` and draws the last image uploaded over it.
    void draw(ivec2 framebufferSize, const vec3& background) const;
    // The window's back buffer as drawn so far (call before the UI is drawn over it).
    static ImageRgb8 readBack(ivec2 framebufferSize);

  private:
    gl::GlTexture m_texture;
    gl::GlFramebuffer m_framebuffer;  // reads m_texture for the blit
    ivec2 m_size{0, 0};
};

}  // namespace relief::viewer
