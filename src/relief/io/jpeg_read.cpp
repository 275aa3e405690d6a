// JPEG through libjpeg-turbo (baseline and progressive, grey or colour). The marker structure is
// walked first: a file without its end-of-image marker is refused as truncated, and damaged
// Huffman tables or scans naming undefined tables are refused before any decoder sees them (the
// checks were written against stb_image, which relief used before; fuzz_jpeg found three bugs in
// Debian's stb_image, the last an undefined shift on corrupt entropy data that no structural
// check can catch, hence libjpeg-turbo). libjpeg's warnings (corrupt data it would decode into
// grey) are errors here: no silent wrong heights.
#include <relief/io/read_common.h>

#include <jpeglib.h>

#include <array>
#include <climits>
#include <csetjmp>
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

// libjpeg reports errors through a callback that must not return: it jumps back to the call
// that set `jump`, with the message kept.
struct JpegErrors {
    jpeg_error_mgr manager;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = "";
};

[[noreturn]] void jpegFail(j_common_ptr cinfo) {
    auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, errors->message);
    std::longjmp(errors->jump, 1);
}

void jpegMessage(j_common_ptr cinfo, int level) {
    if (level < 0) jpegFail(cinfo);  // a warning: corrupt data
}

// One decompression of the bytes: the header only, or the pixels as `channels` (1 or 3) 8-bit
// samples per pixel. No C++ object with a destructor lives between setjmp and the jumps.
struct JpegResult {
    int width = 0, height = 0, components = 0;
    bool ok = false;
};

JpegResult runJpeg(std::span<const unsigned char> bytes, int channels, unsigned char* pixels, char* message) {
    JpegResult result;
    jpeg_decompress_struct cinfo;
    JpegErrors errors;
    cinfo.err = jpeg_std_error(&errors.manager);
    errors.manager.error_exit = jpegFail;
    errors.manager.emit_message = jpegMessage;
    if (setjmp(errors.jump)) {
        jpeg_destroy_decompress(&cinfo);
        std::memcpy(message, errors.message, JMSG_LENGTH_MAX);
        return result;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&cinfo, TRUE);
    result.width = int(cinfo.image_width);
    result.height = int(cinfo.image_height);
    result.components = cinfo.num_components;
    if (pixels) {
        cinfo.out_color_space = channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
        jpeg_start_decompress(&cinfo);
        const size_t stride = size_t(cinfo.output_width) * size_t(channels);
        while (cinfo.output_scanline < cinfo.output_height) {
            JSAMPROW row = pixels + size_t(cinfo.output_scanline) * stride;
            jpeg_read_scanlines(&cinfo, &row, 1);
        }
        jpeg_finish_decompress(&cinfo);
    }
    jpeg_destroy_decompress(&cinfo);
    result.ok = true;
    return result;
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
        char message[JMSG_LENGTH_MAX] = "";
        const JpegResult header = runJpeg(m_bytes, 1, nullptr, message);
        if (!header.ok) return corrupt(message);
        if (header.components != 1 && header.components != 3)
            return makeError(ErrorKind::Unsupported, "{}: JPEG with {} components (CMYK?): only grey or colour",
                             m_file.path(), header.components);
        m_components = header.components;
        m_width = header.width;
        m_height = header.height;
        return ImageHeader{header.width, header.height, false};
    }

    // 8-bit pixels with `channels` (1 or 3) per pixel, row by row.
    Result<std::vector<unsigned char>> decode(int channels) {
        std::vector<unsigned char> pixels(size_t(m_width) * size_t(m_height) * size_t(channels));
        char message[JMSG_LENGTH_MAX] = "";
        if (!runJpeg(m_bytes, channels, pixels.data(), message).ok) return corrupt(message);
        return pixels;
    }

    int channels() const { return m_components >= 3 ? 3 : 1; }
    // decode()'s buffer; readHeader already holds the compressed file.
    int64_t scratchBytes() const {
        return int64_t(m_width) * m_height * channels() + int64_t(m_bytes.size());
    }

private:
    Error corrupt(const char* reason) const {
        return makeError(ErrorKind::InvalidInput, "{}: corrupt or unsupported JPEG: {}", m_file.path(), reason);
    }

    FileReader& m_file;
    std::vector<unsigned char> m_bytes;
    int m_components = 0, m_width = 0, m_height = 0;
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
    int64_t scratchBytes() const override { return m_stream.scratchBytes(); }

    Status readPixels(std::span<float> pixels) override {
        const PixelLayout layout{Scalar::U8, std::endian::native, m_stream.channels()};
        auto data = m_stream.decode(layout.channels);
        if (!data) return data.error();
        const size_t stride = rowBytes(layout, m_width);
        for (size_t y = 0; y < pixels.size() / size_t(m_width); ++y)
            convertRow(data->data() + y * stride, layout, m_width, m_select,
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
    int64_t scratchBytes() const override { return m_stream.scratchBytes(); }

    Status readPixels(std::span<Rgb8> pixels) override {
        auto data = m_stream.decode(3);
        if (!data) return data.error();
        std::memcpy(pixels.data(), data->data(), pixels.size_bytes());
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
