// OpenEXR through Imf::InputFile (scanline or tiled, any compression, half/float/uint channels,
// read as float). Height comes from Y, else R/G/B luminance, else the only channel; --channel
// picks R, G, B or A by name. OpenEXR reports errors by exception; none leaves this file.
#include <relief/io/exr_stream.h>
#include <relief/core/parallel.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfThreading.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
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

int exrWriteThreads() {
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

namespace {

std::vector<std::string> channelNames(const Imf::ChannelList& channels) {
    std::vector<std::string> names;
    for (auto it = channels.begin(); it != channels.end(); ++it) names.emplace_back(it.name());
    return names;
}

// The channels to read: one (used as is) or R, G, B (reduced to luminance).
Result<std::vector<std::string>> chooseChannels(const std::string& path,
                                                const Imf::ChannelList& channels,
                                                ChannelSelect select) {
    const std::vector<std::string> all = channelNames(channels);
    auto has = [&](const char* name) { return channels.findChannel(name) != nullptr; };
    const bool rgb = has("R") && has("G") && has("B");
    const char* grey = has("Y") ? "Y" : all.size() == 1 ? all[0].c_str() : nullptr;
    const char* named[] = {"R", "G", "B", "A"};
    if (select == ChannelSelect::Luminance) {
        if (has("Y")) return std::vector<std::string>{"Y"};
        if (rgb) return std::vector<std::string>{"R", "G", "B"};
        if (grey) return std::vector<std::string>{grey};
        return makeError(ErrorKind::Unsupported,
                         "{}: EXR has no Y, no R/G/B and not a single channel to use as height "
                         "(channels: {})",
                         path, fmt::join(all, ", "));
    }
    const char* wanted = named[int(select) - int(ChannelSelect::Red)];
    if (has(wanted)) return std::vector<std::string>{wanted};
    if (select != ChannelSelect::Alpha && grey) return std::vector<std::string>{grey};
    return makeError(ErrorKind::BadArgument, "--channel {}: {} has no such channel (channels: {})",
                     char(std::tolower(wanted[0])), path, fmt::join(all, ", "));
}

class ExrHeightDecoder final : public HeightDecoder {
public:
    ExrHeightDecoder(FileReader& file, ChannelSelect select)
        : m_stream(file), m_path(file.path()), m_select(select) {}

    Result<ImageHeader> readHeader() override {
        try {
            limitExrSizes();
            if (auto problem = exrHeaderProblem(m_stream.file()))
                return makeError(ErrorKind::InvalidInput, "{}: truncated or corrupt EXR: {}",
                                 m_path, *problem);
            m_file = std::make_unique<Imf::InputFile>(m_stream);
            const Imf::Header& header = m_file->header();
            auto names = chooseChannels(m_path, header.channels(), m_select);
            if (!names) return names.error();
            m_names = std::move(*names);
            for (const std::string& name : m_names) {
                const Imf::Channel* channel = header.channels().findChannel(name);
                if (channel->xSampling != 1 || channel->ySampling != 1)
                    return makeError(ErrorKind::Unsupported,
                                     "{}: EXR channel {} is subsampled", m_path, name);
            }
            const Imath::Box2i window = header.dataWindow();
            return ImageHeader{int64_t(window.max.x) - window.min.x + 1,
                               int64_t(window.max.y) - window.min.y + 1, true};
        } catch (const std::exception& e) {
            return failure(e);
        }
    }

    Status readPixels(std::span<float> pixels) override {
        try {
            readChunks(pixels);
        } catch (const std::exception& e) {
            return failure(e);
        }
        return {};
    }

private:
    // A band of rows at a time, interleaved, so colour needs no full-size planes.
    void readChunks(std::span<float> pixels) {
        constexpr int kRows = 64;
        const Imath::Box2i window = m_file->header().dataWindow();
        const int64_t width = int64_t(window.max.x) - window.min.x + 1;
        const PixelLayout layout{Scalar::F32, std::endian::native, int(m_names.size())};
        const size_t pixelBytes = sizeof(float) * m_names.size();
        std::vector<float> band(size_t(width) * kRows * m_names.size());
        for (int y0 = window.min.y; y0 <= window.max.y; y0 += kRows) {
            const int rows = std::min(kRows, window.max.y - y0 + 1);
            Imf::FrameBuffer frame;
            for (size_t c = 0; c < m_names.size(); ++c)
                frame.insert(m_names[c], Imf::Slice::Make(Imf::FLOAT, band.data() + c,
                                                          Imath::V2i(window.min.x, y0), width,
                                                          rows, pixelBytes, pixelBytes * width));
            m_file->setFrameBuffer(frame);
            m_file->readPixels(y0, y0 + rows - 1);
            for (int r = 0; r < rows; ++r) {
                const auto* row = reinterpret_cast<const unsigned char*>(band.data()) +
                                  size_t(r) * pixelBytes * width;
                const int64_t y = int64_t(y0) - window.min.y + r;
                convertRow(row, layout, width, ChannelSelect::Luminance,
                           pixels.data() + y * width);
            }
        }
    }

    Error failure(const std::exception& e) const {
        return makeError(ErrorKind::InvalidInput, "{}: truncated or corrupt EXR: {}", m_path,
                         e.what());
    }

    ExrInputStream m_stream;
    std::string m_path;
    ChannelSelect m_select;
    std::unique_ptr<Imf::InputFile> m_file;
    std::vector<std::string> m_names;
};

}  // namespace

std::unique_ptr<HeightDecoder> makeExrHeightDecoder(FileReader& file, ChannelSelect select) {
    return std::make_unique<ExrHeightDecoder>(file, select);
}

}  // namespace relief
