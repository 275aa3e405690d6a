// OpenEXR through Imf::InputFile (scanline or tiled, any compression, half/float/uint channels,
// read as float). Height comes from Y, else R/G/B luminance, else the only channel; --channel
// picks R, G, B or A by name. OpenEXR reports errors by exception; none leaves this file.
#include <relief/io/exr_stream.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace relief {

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
            m_file = std::make_unique<Imf::InputFile>(m_stream, exrThreads());
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
