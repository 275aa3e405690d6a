#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <png.h>
#include <relief/io/image_write.h>
#include <relief/io/exr_stream.h>
#include <relief/io/npy.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace relief {

namespace {

// libpng's messages become relief's error (no stray "libpng error:" line on stderr).
struct PngErrors {
    std::string message;
};

extern "C" void pngError(png_structp png, png_const_charp message) {
    static_cast<PngErrors*>(png_get_error_ptr(png))->message = message ? message : "";
    png_longjmp(png, 1);
}

extern "C" void pngWarning(png_structp, png_const_charp) {}

// One output set of its own, committed at once.
Status writeOne(const std::function<Status(OutputSet&)>& add) {
    OutputSet outputs;
    if (Status added = add(outputs); !added) return added;
    return outputs.commit();
}

}  // namespace

Status writeAtomically(const std::string& path,
                       const std::function<Status(const std::string& tempPath)>& write) {
    return writeOne([&](OutputSet& outputs) { return outputs.add(path, write); });
}

Status writeTextFile(const std::string& path, const std::string& text) {
    return writeOne([&](OutputSet& outputs) { return outputs.addText(path, text); });
}

Status writePng(const std::string& path, const ImageRgb8& image) {
    return writeOne([&](OutputSet& outputs) { return writePng(outputs, path, image); });
}

Status writeExr(const std::string& path, const ImageF& image) {
    return writeOne([&](OutputSet& outputs) { return writeExr(outputs, path, image); });
}

Status writePng(OutputSet& outputs, const std::string& path, const ImageRgb8& image) {
    return outputs.add(path, [&](const std::string& temp) -> Status {
        FILE* file = std::fopen(temp.c_str(), "wb");
        if (!file)
            return makeError(ErrorKind::Io, "{}: cannot open for writing: {}", path,
                             std::strerror(errno));
        PngErrors errors;
        png_structp png =
            png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, pngError, pngWarning);
        png_infop info = png ? png_create_info_struct(png) : nullptr;
        if (!png || !info || setjmp(png_jmpbuf(png))) {
            const int error = errno;
            png_destroy_write_struct(&png, &info);
            std::fclose(file);
            return makeError(ErrorKind::Io, "{}: PNG write failed: {}{}", path, errors.message,
                             error ? std::string(": ") + std::strerror(error) : "");
        }
        png_init_io(png, file);
        png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB,
                     PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        errno = 0;
        png_write_info(png, info);
        for (int y = 0; y < image.height; ++y)
            png_write_row(png, reinterpret_cast<png_const_bytep>(&image.at(0, y)));
        png_write_end(png, nullptr);
        png_destroy_write_struct(&png, &info);
        const bool failed = std::ferror(file) != 0;
        if (std::fclose(file) != 0 || failed)
            return makeError(ErrorKind::Io, "{}: write failed: {}", path, std::strerror(errno));
        return {};
    });
}

Status writeExr(OutputSet& outputs, const std::string& path, const ImageF& image) {
    return outputs.add(path, [&](const std::string& temp) -> Status {
        try {
            Imf::Header header(image.width, image.height);
            header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
            Imf::OutputFile file(temp.c_str(), header, exrThreads());
            Imf::FrameBuffer frame;
            frame.insert("Y", Imf::Slice(Imf::FLOAT, (char*)image.pixels.data(), sizeof(float),
                                         sizeof(float) * size_t(image.width)));
            file.setFrameBuffer(frame);
            file.writePixels(image.height);
        } catch (const std::exception& e) {
            return makeError(ErrorKind::Io, "{}: EXR write failed: {}", path, e.what());
        }
        return {};
    });
}

namespace {

void appendRow(std::string& out, const ImageF& image, int y) {
    out.append(reinterpret_cast<const char*>(&image.at(0, y)), sizeof(float) * size_t(image.width));
}

}  // namespace

Status writePfm(OutputSet& outputs, const std::string& path, const ImageF& image) {
    // A negative scale says little endian (the floats as this machine holds them).
    std::string out = fmt::format("Pf\n{} {}\n-1.0\n", image.width, image.height);
    for (int y = image.height; y-- > 0;) appendRow(out, image, y);
    return outputs.addText(path, out);
}

Status writeNpy(OutputSet& outputs, const std::string& path, const ImageF& image) {
    const NpyField f4[] = {{"", "<f4"}};
    const int64_t shape[] = {image.height, image.width};
    std::string out = npyPreamble(f4, shape);
    for (int y = 0; y < image.height; ++y) appendRow(out, image, y);
    return outputs.addText(path, out);
}

Status writeFloatImage(OutputSet& outputs, const std::string& path, const ImageF& image) {
    if (hasExtension(path, ".npy")) return writeNpy(outputs, path, image);
    if (hasExtension(path, ".pfm")) return writePfm(outputs, path, image);
    return writeExr(outputs, path, image);
}

}  // namespace relief
