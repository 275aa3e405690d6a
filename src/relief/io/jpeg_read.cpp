// JPEG through stb_image (baseline and progressive, grey or colour). stb_image decodes a truncated
// stream without complaint, filling the rest with grey, so the marker structure is walked first:
// a file without its end-of-image marker is refused as truncated.
#include <relief/io/read_common.h>

#include <array>

#include <stb/stb_image.h>

#include <climits>
#include <cstring>

namespace relief {

namespace {

bool isStandaloneMarker(unsigned char marker) {
    return marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8);  // TEM, RSTn, SOI
}

// Returns the position of the next marker after entropy-coded data starting at `pos`, or
// bytes.size() if the data runs to the end of the file.
size_t skipEntropyData(std::span<const unsigned char> bytes, size_t pos) {
    for (; pos + 1 < bytes.size(); ++pos) {
        const unsigned char next = bytes[pos + 1];
        if (bytes[pos] == 0xff && next != 0x00 && next != 0xff && !(next >= 0xd0 && next <= 0xd7))
            return pos;
    }
    return bytes.size();
}

// stb_image decodes 8-bit Huffman-coded frames (SOF0-2); name the other variants rather than
// let them fail as "corrupt".
Status checkFrame(const std::string& path, unsigned char marker,
                  std::span<const unsigned char> segment) {
    const bool isFrame = marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 &&
                         marker != 0xcc;  // DHT, JPG and DAC share the range
    if (!isFrame) return {};
    if (marker > 0xc2)
        return makeError(ErrorKind::Unsupported,
                         "{}: JPEG variant not supported (frame type 0x{:x}: lossless, "
                         "hierarchical or arithmetic-coded)",
                         path, marker);
    if (!segment.empty() && segment[0] != 8)
        return makeError(ErrorKind::Unsupported, "{}: {}-bit JPEG not supported (8-bit only)",
                         path, segment[0]);
    return {};
}

// stb_image builds each Huffman table without checking that its 16 code counts add up to at most
// 256 symbols, and writes past its 257-entry size table when they do (found by fuzz_jpeg). A DHT
// segment holds tables of: class/id, 16 counts, then as many symbols as the counts add up to.
// `defined` records the tables seen, indexed class * 4 + id.
bool readHuffmanTables(std::span<const unsigned char> segment, std::array<bool, 8>& defined) {
    size_t pos = 0;
    while (pos < segment.size()) {
        if (pos + 17 > segment.size()) return false;
        const unsigned tableClass = segment[pos] >> 4, id = segment[pos] & 15;
        if (tableClass > 1 || id > 3) return false;
        size_t symbols = 0;
        for (size_t i = 1; i <= 16; ++i) symbols += segment[pos + i];
        if (symbols > 256) return false;
        defined[tableClass * 4 + id] = true;
        pos += 17 + symbols;
    }
    return pos == segment.size();
}

// stb_image also decodes a scan with a Huffman table no DHT defined, reading an uninitialized
// table and indexing far out of bounds (found by fuzz_jpeg: a progressive AC scan with only a DC
// table). An SOS segment: component count, (component, DC id << 4 | AC id) each, then Ss, Se, A;
// a scan uses DC tables when Ss = 0 and AC tables when Se > 0.
bool scanTablesDefined(std::span<const unsigned char> segment, const std::array<bool, 8>& defined) {
    if (segment.empty()) return false;
    const size_t components = segment[0];
    if (segment.size() < 1 + 2 * components + 3) return false;
    const unsigned spectralStart = segment[1 + 2 * components], spectralEnd = segment[2 + 2 * components];
    for (size_t k = 0; k < components; ++k) {
        const unsigned dc = segment[2 + 2 * k] >> 4, ac = segment[2 + 2 * k] & 15;
        if (spectralStart == 0 && (dc > 3 || !defined[dc])) return false;
        if (spectralEnd > 0 && (ac > 3 || !defined[4 + ac])) return false;
    }
    return true;
}

// Walks the segments from SOI to EOI; segment lengths are trusted only as far as the file goes.
Status checkJpegStructure(const std::string& path, std::span<const unsigned char> bytes) {
    auto truncated = [&] {
        return makeError(ErrorKind::InvalidInput,
                         "{}: truncated JPEG (no end-of-image marker; the file ends early)", path);
    };
    size_t pos = 2;  // after SOI
    std::array<bool, 8> huffmanDefined{};
    while (true) {
        while (pos + 1 < bytes.size() && bytes[pos] == 0xff && bytes[pos + 1] == 0xff) ++pos;
        if (pos + 2 > bytes.size()) return truncated();
        if (bytes[pos] != 0xff)
            return makeError(ErrorKind::InvalidInput,
                             "{}: corrupt JPEG: expected a marker at byte {}", path, pos);
        const unsigned char marker = bytes[pos + 1];
        if (marker == 0xd9) return {};  // EOI
        pos += 2;
        if (isStandaloneMarker(marker)) continue;
        if (pos + 2 > bytes.size()) return truncated();
        const size_t length = size_t(bytes[pos]) << 8 | bytes[pos + 1];
        if (length < 2)
            return makeError(ErrorKind::InvalidInput, "{}: corrupt JPEG: bad segment length",
                             path);
        const size_t segment = pos + 2;
        pos += length;
        if (pos > bytes.size()) return truncated();
        if (Status s = checkFrame(path, marker, bytes.subspan(segment, length - 2)); !s) return s;
        if (marker == 0xc4 && !readHuffmanTables(bytes.subspan(segment, length - 2), huffmanDefined))
            return makeError(ErrorKind::InvalidInput,
                             "{}: corrupt JPEG: bad Huffman table at byte {}", path, segment);
        if (marker == 0xda && !scanTablesDefined(bytes.subspan(segment, length - 2), huffmanDefined))
            return makeError(ErrorKind::InvalidInput,
                             "{}: corrupt JPEG: scan at byte {} uses a Huffman table that is not defined",
                             path, segment);
        if (marker == 0xda) pos = skipEntropyData(bytes, pos);  // SOS: scan data follows
    }
}

// The whole file in memory (JPEG is compressed, so this is small next to the pixels), checked,
// with its size and component count from the header.
class JpegStream {
public:
    explicit JpegStream(FileReader& file) : m_file(file) {}

    Result<ImageHeader> readHeader() {
        if (m_file.size() > INT_MAX)
            return makeError(ErrorKind::Unsupported, "{}: JPEG files over 2 GiB are not supported",
                             m_file.path());
        auto bytes = m_file.readAll();
        if (!bytes) return bytes.error();
        m_bytes = std::move(*bytes);
        if (Status s = checkJpegStructure(m_file.path(), m_bytes); !s) return s.error();
        int w = 0, h = 0;
        if (!stbi_info_from_memory(m_bytes.data(), int(m_bytes.size()), &w, &h, &m_components))
            return corrupt();
        return ImageHeader{w, h, false};
    }

    // 8-bit pixels with `channels` (1 or 3) per pixel; freed by the caller with stbi_image_free.
    Result<unsigned char*> decode(int channels) {
        int w = 0, h = 0, n = 0;
        unsigned char* data =
            stbi_load_from_memory(m_bytes.data(), int(m_bytes.size()), &w, &h, &n, channels);
        if (!data) return corrupt();
        return data;
    }

    int channels() const { return m_components >= 3 ? 3 : 1; }

private:
    Error corrupt() const {
        return makeError(ErrorKind::InvalidInput, "{}: corrupt or unsupported JPEG: {}",
                         m_file.path(), stbi_failure_reason());
    }

    FileReader& m_file;
    std::vector<unsigned char> m_bytes;
    int m_components = 0;
};

struct StbFree {
    void operator()(unsigned char* data) const { stbi_image_free(data); }
};

class JpegHeightDecoder final : public HeightDecoder {
public:
    JpegHeightDecoder(FileReader& file, ChannelSelect select)
        : m_stream(file), m_path(file.path()), m_select(select) {}

    Result<ImageHeader> readHeader() override {
        auto header = m_stream.readHeader();
        if (!header) return header;
        if (Status s = checkChannel(m_path, m_stream.channels(), m_select); !s) return s.error();
        m_width = header->width;
        return header;
    }

    Status readPixels(std::span<float> pixels) override {
        const PixelLayout layout{Scalar::U8, std::endian::native, m_stream.channels()};
        auto data = m_stream.decode(layout.channels);
        if (!data) return data.error();
        std::unique_ptr<unsigned char, StbFree> owned(*data);
        const size_t stride = rowBytes(layout, m_width);
        for (size_t y = 0; y < pixels.size() / size_t(m_width); ++y)
            convertRow(owned.get() + y * stride, layout, m_width, m_select,
                       pixels.data() + y * size_t(m_width));
        return {};
    }

private:
    JpegStream m_stream;
    std::string m_path;
    ChannelSelect m_select;
    int64_t m_width = 0;
};

class JpegColorDecoder final : public ColorDecoder {
public:
    explicit JpegColorDecoder(FileReader& file) : m_stream(file) {}

    Result<ImageHeader> readHeader() override { return m_stream.readHeader(); }

    Status readPixels(std::span<Rgb8> pixels) override {
        auto data = m_stream.decode(3);
        if (!data) return data.error();
        std::unique_ptr<unsigned char, StbFree> owned(*data);
        std::memcpy(pixels.data(), owned.get(), pixels.size_bytes());
        return {};
    }

private:
    JpegStream m_stream;
};

}  // namespace

std::unique_ptr<HeightDecoder> makeJpegHeightDecoder(FileReader& file, ChannelSelect select) {
    return std::make_unique<JpegHeightDecoder>(file, select);
}

std::unique_ptr<ColorDecoder> makeJpegColorDecoder(FileReader& file) {
    return std::make_unique<JpegColorDecoder>(file);
}

}  // namespace relief
