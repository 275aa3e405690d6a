// PFM: "Pf" (grey) or "PF" (RGB), width, height and a scale whose sign gives the byte order
// (negative: little endian), each followed by whitespace, then 32-bit floats with the bottom row
// first. Bytes after the samples are ignored, as the format's readers customarily do.
#include <relief/io/read_common.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <string_view>

namespace relief {

namespace {

struct PfmHeader {
    int channels = 1;
    int64_t width = 0;
    int64_t height = 0;
    std::endian endian = std::endian::little;
    size_t dataOffset = 0;
};

// Splits "W H SCALE" after the two-byte magic; the data starts after the line break that ends SCALE
// (one whitespace byte, or CR LF as Windows writers put it). Between the magic, W, H and SCALE,
// '#' comment lines are skipped, as some writers add them (netpbm's habit; PFM has no rule).
bool parsePfmHeader(std::span<const unsigned char> head, PfmHeader& header) {
    const std::string_view text(reinterpret_cast<const char*>(head.data()), head.size());
    size_t pos = 2;
    auto token = [&]() -> std::string_view {
        const size_t start = pos;
        for (;;) {
            while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
            if (pos == start || pos >= text.size() || text[pos] != '#') break;
            while (pos < text.size() && text[pos] != '\n') ++pos;
        }
        if (pos == start) return {};  // a token must follow whitespace
        const size_t begin = pos;
        while (pos < text.size() && !std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
        return text.substr(begin, pos - begin);
    };
    auto number = [](std::string_view s, auto& value) {
        auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
        return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
    };
    double scale = 0.0;
    if (!number(token(), header.width) || !number(token(), header.height) ||
        !number(token(), scale) || pos >= text.size() || !std::isfinite(scale) || scale == 0.0)
        return false;
    header.channels = head[1] == 'F' ? 3 : 1;
    header.endian = scale < 0.0 ? std::endian::little : std::endian::big;
    const bool crlf = text[pos] == '\r' && pos + 1 < text.size() && text[pos + 1] == '\n';
    header.dataOffset = pos + (crlf ? 2 : 1);
    return true;
}

class PfmHeightDecoder final : public HeightDecoder {
public:
    PfmHeightDecoder(FileReader& file, ChannelSelect select) : m_file(file), m_select(select) {}

    Result<ImageHeader> readHeader() override {
        if (!parsePfmHeader(m_file.head(), m_header))
            return makeError(ErrorKind::InvalidInput,
                             "{}: bad PFM header (expected 'PF' or 'Pf', width, height and a "
                             "non-zero scale, separated by whitespace)",
                             m_file.path());
        if (Status s = checkChannel(m_file.path(), m_header.channels, m_select); !s)
            return s.error();
        if (Status s = checkDataSize(); !s) return s.error();
        return ImageHeader{m_header.width, m_header.height, true};
    }

    Status readPixels(std::span<float> pixels) override {
        if (!m_file.seek(int64_t(m_header.dataOffset)))
            return makeError(ErrorKind::Io, "{}: cannot read", m_file.path());
        return readRows(m_file, layout(), m_select, true, m_header.width, pixels);
    }

private:
    PixelLayout layout() const { return {Scalar::F32, m_header.endian, m_header.channels}; }

    // Before allocating: a header promising more than the file holds is refused right away.
    Status checkDataSize() const {
        const int64_t needed = imageBytes(layout(), m_header.width, m_header.height);
        const int64_t present = m_file.size() - int64_t(m_header.dataOffset);
        if (needed >= 0 && present < needed)
            return makeError(ErrorKind::InvalidInput,
                             "{}: truncated PFM: {}x{} needs {} bytes of samples, the file has {}",
                             m_file.path(), m_header.width, m_header.height, needed, present);
        return {};
    }

    FileReader& m_file;
    ChannelSelect m_select;
    PfmHeader m_header;
};

}  // namespace

std::unique_ptr<HeightDecoder> makePfmHeightDecoder(FileReader& file, ChannelSelect select) {
    return std::make_unique<PfmHeightDecoder>(file, select);
}

}  // namespace relief
