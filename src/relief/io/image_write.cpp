#include <relief/io/image_write.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <png.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

namespace relief {

namespace {

// Temp files being written right now, so SIGINT / SIGTERM can remove them (unlink is
// async-signal-safe) and leave no partial output behind.
constexpr int kTempSlots = 64;
std::atomic<const char*> gTempFiles[kTempSlots];

extern "C" void removeTempFilesAndExit(int signal) {
    for (auto& slot : gTempFiles)
        if (const char* path = slot.load()) ::unlink(path);
    ::signal(signal, SIG_DFL);
    ::raise(signal);
}

void installSignalCleanup() {
    static const bool installed = [] {
        struct sigaction action {};
        action.sa_handler = removeTempFilesAndExit;
        sigemptyset(&action.sa_mask);
        sigaction(SIGINT, &action, nullptr);
        sigaction(SIGTERM, &action, nullptr);
        return true;
    }();
    (void)installed;
}

// Registers a temp path for the signal handler while alive.
class TempFileGuard {
public:
    explicit TempFileGuard(const std::string& path) : m_path(path) {
        installSignalCleanup();
        for (auto& slot : gTempFiles) {
            const char* expected = nullptr;
            if (slot.compare_exchange_strong(expected, m_path.c_str())) {
                m_slot = &slot;
                break;
            }
        }
    }
    ~TempFileGuard() {
        if (m_slot) m_slot->store(nullptr);
    }

private:
    std::string m_path;
    std::atomic<const char*>* m_slot = nullptr;
};

}  // namespace

Status writeAtomically(const std::string& path,
                       const std::function<Status(const std::string& tempPath)>& write) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        return makeError(ErrorKind::Io, "{}: folder '{}' does not exist", path, folder.string());
    const std::string temp = (folder / ("." + target.filename().string() + ".tmp." +
                                        std::to_string(::getpid()) + "." +
                                        std::to_string(std::random_device{}())))
                                 .string();
    const TempFileGuard guard(temp);
    Status status = write(temp);
    if (status) {
        fs::rename(temp, target, ec);
        if (ec) status = makeError(ErrorKind::Io, "{}: cannot rename into place: {}", path, ec.message());
    }
    if (!status) fs::remove(temp, ec);
    return status;
}

Status writeTextFile(const std::string& path, const std::string& text) {
    return writeAtomically(path, [&](const std::string& temp) -> Status {
        std::ofstream out(temp, std::ios::binary);
        out << text;
        out.close();
        if (!out) return makeError(ErrorKind::Io, "{}: write failed", path);
        return {};
    });
}

Status writePng(const std::string& path, const ImageRgb8& image) {
    return writeAtomically(path, [&](const std::string& temp) -> Status {
        FILE* file = std::fopen(temp.c_str(), "wb");
        if (!file) return makeError(ErrorKind::Io, "{}: cannot open for writing", path);
        png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
        png_infop info = png ? png_create_info_struct(png) : nullptr;
        if (!png || !info || setjmp(png_jmpbuf(png))) {
            png_destroy_write_struct(&png, &info);
            std::fclose(file);
            return makeError(ErrorKind::Io, "{}: PNG encoding failed", path);
        }
        png_init_io(png, file);
        png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB,
                     PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_write_info(png, info);
        for (int y = 0; y < image.height; ++y)
            png_write_row(png, reinterpret_cast<png_const_bytep>(&image.at(0, y)));
        png_write_end(png, nullptr);
        png_destroy_write_struct(&png, &info);
        if (std::fclose(file) != 0) return makeError(ErrorKind::Io, "{}: write failed", path);
        return {};
    });
}

Status writeExr(const std::string& path, const ImageF& image) {
    return writeAtomically(path, [&](const std::string& temp) -> Status {
        try {
            Imf::Header header(image.width, image.height);
            header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
            Imf::OutputFile file(temp.c_str(), header);
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

}  // namespace relief
