#include <relief/viewer/image_display.h>

#include <algorithm>

namespace relief::viewer {

ImageDisplay::ImageDisplay() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    m_framebuffer = gl::GlFramebuffer(id);
}

void ImageDisplay::upload(const ImageRgb8& image) {
    if (image.width < 1 || image.height < 1) return;
    const ivec2 size(image.width, image.height);
    if (size != m_size) {  // immutable storage: a new size is a new texture
        GLuint id = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &id);
        m_texture = gl::GlTexture(id);
        glTextureStorage2D(id, 1, GL_RGBA8, size.x, size.y);
        glNamedFramebufferTexture(m_framebuffer.id(), GL_COLOR_ATTACHMENT0, id, 0);
        m_size = size;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // Rgb8 rows are tightly packed
    glTextureSubImage2D(m_texture.id(), 0, 0, 0, size.x, size.y, GL_RGB, GL_UNSIGNED_BYTE,
                        image.pixels.data());
}

void ImageDisplay::draw(ivec2 framebufferSize, const vec3& background) const {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, framebufferSize.x, framebufferSize.y);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(background.x, background.y, background.z, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    if (m_size.x < 1 || framebufferSize.x < 1 || framebufferSize.y < 1) return;
    const float scale = std::min(float(framebufferSize.x) / float(m_size.x),
                                 float(framebufferSize.y) / float(m_size.y));
    const ivec2 drawn = glm::max(ivec2(vec2(m_size) * scale + 0.5f), ivec2(1));
    const ivec2 corner = (framebufferSize - drawn) / 2;
    // Texture row 0 is the image's top row: blit it to the top of the rectangle.
    glBlitNamedFramebuffer(m_framebuffer.id(), 0, 0, 0, m_size.x, m_size.y, corner.x,
                           corner.y + drawn.y, corner.x + drawn.x, corner.y, GL_COLOR_BUFFER_BIT,
                           GL_LINEAR);
}

ImageRgb8 ImageDisplay::readBack(ivec2 framebufferSize) {
    ImageRgb8 image(framebufferSize.x, framebufferSize.y);
    std::vector<Rgb8> rows(image.pixels.size());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, image.width, image.height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
    for (int y = 0; y < image.height; ++y)  // GL's row 0 is the bottom one
        std::copy_n(rows.begin() + ptrdiff_t(image.height - 1 - y) * image.width, image.width,
                    image.pixels.begin() + ptrdiff_t(y) * image.width);
    return image;
}

}  // namespace relief::viewer
