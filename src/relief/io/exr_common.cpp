// What the OpenEXR readers and writers share (exr_stream.h): the size limits, the worker pool's
// size and the header walk made before OpenEXR sees a header.
#include <relief/io/exr_stream.h>
#include <relief/core/parallel.h>

#include <ImfHeader.h>
#include <ImfThreading.h>

#include <algorithm>
#include <mutex>

namespace relief {

// Without these limits a damaged header makes OpenEXR allocate offset tables for any size.
void limitExrSizes() {
    static std::once_flag once;
    std::call_once(once, [] {
        Imf::Header::setMaxImageSize(kMaxDimension, kMaxDimension);
        Imf::Header::setMaxTileSize(kMaxDimension, kMaxDimension);
    });
}

int exrThreads() {
    static std::mutex mutex;  // the pool is the process's: size it once per limit, not per file
    const std::lock_guard lock(mutex);
    const int threads = std::max(1, ThreadLimit::current());
    if (Imf::globalThreadCount() != threads) Imf::setGlobalThreadCount(threads);
    return threads;
}

namespace {

// The bytes OpenEXR 3.1 consumes for a value of a fixed-size attribute type, whatever its size
// field says; 0 for other types.
int64_t fixedValueBytes(const std::string& type) {
    static const std::pair<const char*, int> kFixed[] = {
        {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1},
        {"deepImageState", 1}, {"double", 8}, {"envmap", 1}, {"float", 4}, {"int", 4},
        {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72}, {"m44f", 64},
        {"m44d", 128}, {"rational", 8}, {"tiledesc", 9}, {"timecode", 8}, {"v2i", 8},
        {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24}};
    for (const auto& [name, bytes] : kFixed)
        if (type == name) return bytes;
    return 0;
}

}  // namespace

// Follows OpenEXR 3.1's header parser (Header::readFrom and the attributes' readValueFrom): most
// values are read by their size field, but fixed-size types, channel lists, previews and string
// vectors consume what their own content says, and each of those sizes is checked here before
// OpenEXR allocates it.
std::optional<std::string> exrHeaderProblem(FileReader& file) {
    auto corrupt = [](std::string what) { return std::optional<std::string>(std::move(what)); };
    unsigned char start[8];
    if (!file.seek(0) || !file.read(start, sizeof start))
        return corrupt("the file ends in its header");
    const bool multipart = (start[5] & 0x10) != 0;  // bit 12 of the version field
    auto readName = [&](std::string& name) {
        name.clear();
        for (char c; file.read(&c, 1) && name.size() <= 255;) {
            if (c == '\0') return true;
            name += c;
        }
        return false;
    };
    auto readInt = [&](int64_t& value) {
        unsigned char b[4];
        if (!file.read(b, sizeof b)) return false;
        value = int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 |
                        uint32_t(b[3]) << 24);
        return true;
    };
    auto skip = [&](int64_t bytes) {  // false if the file has fewer bytes left
        return bytes >= 0 && bytes <= file.size() - file.tell() && file.seek(file.tell() + bytes);
    };
    std::string name, type, channel;
    while (true) {  // one header, or (multi-part) headers until an empty one
        int attributes = 0;
        while (true) {
            if (!readName(name)) return corrupt("the header is cut short or damaged");
            if (name.empty()) break;
            int64_t size = 0;
            if (!readName(type) || !readInt(size))
                return corrupt(fmt::format("attribute '{}' is cut short", name));
            const auto tooLong = [&] {
                return corrupt(fmt::format("attribute '{}' ({}) claims more bytes than the file "
                                           "has left",
                                           name, type));
            };
            if (const int64_t fixed = fixedValueBytes(type)) {
                if (!skip(fixed)) return tooLong();
            } else if (type == "chlist") {
                while (true) {
                    if (!readName(channel)) return tooLong();
                    if (channel.empty()) break;
                    if (!skip(16)) return tooLong();
                }
            } else if (type == "preview") {
                int64_t width = 0, height = 0;
                if (!readInt(width) || !readInt(height)) return tooLong();
                // Two 32-bit sizes: their product fits in 64 bits unsigned, times 4 may not.
                const uint64_t pixels = uint64_t(uint32_t(width)) * uint64_t(uint32_t(height));
                if (pixels > uint64_t(file.size()) / 4 || !skip(int64_t(pixels) * 4)) return tooLong();
            } else if (type == "stringvector") {
                for (int64_t read = 0, length = 0; read < size; read += 4 + length)
                    if (!readInt(length) || !skip(length)) return tooLong();
            } else if (!skip(size)) {
                return tooLong();
            }
            ++attributes;
        }
        if (!multipart || attributes == 0) break;
    }
    return file.seek(0) ? std::nullopt : corrupt("cannot seek");
}

}  // namespace relief
