// Placeholder readers: PNG/JPEG through stb_image. To be replaced by the full readers.
#include <relief/io/heightfield_io.h>

#include <stb/stb_image.h>

#include <cstring>

namespace relief {

Result<Heightfield> loadHeightfieldFile(const std::string& path, const LoadOptions& options) {
    int w = 0, h = 0, n = 0;
    stbi_us* data = stbi_load_16(path.c_str(), &w, &h, &n, 1);
    if (!data) return makeError(ErrorKind::Io, "{}: cannot read: {}", path, stbi_failure_reason());
    Heightfield hf;
    hf.width = w;
    hf.height = h;
    hf.samples.resize(size_t(w) * size_t(h));
    for (size_t k = 0; k < hf.samples.size(); ++k) hf.samples[k] = float(data[k]) / 65535.0f;
    stbi_image_free(data);
    return hf;
}

Result<ImageRgb8> loadColorImage(const std::string& path) {
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
    if (!data) return makeError(ErrorKind::Io, "{}: cannot read: {}", path, stbi_failure_reason());
    ImageRgb8 image(w, h);
    std::memcpy(image.pixels.data(), data, size_t(w) * size_t(h) * 3);
    stbi_image_free(data);
    return image;
}

}  // namespace relief
