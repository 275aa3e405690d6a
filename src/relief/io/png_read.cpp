// PNG through libpng: every bit depth and colour type, interlaced or not. libpng reports errors
// by longjmp, so the functions that call setjmp hold no objects with destructors that a jump could
// skip, and libpng's messages are captured instead of printed.
#include <relief/io/read_common.h>

#include <png.h>

#include <cstring>
#include <functional>

namespace relief {

namespace {

enum class PngTarget { Height, Color };

class PngStream {
public:
    PngStream(FileReader& file, int64_t maxSamples) : m_file(file), m_maxSamples(maxSamples) {
        m_png = png_create_read_struct(PNG_LIBPNG_VER_STRING, this, onError, onWarning);
        if (m_png) m_info = png_create_info_struct(m_png);
    }
    ~PngStream() { png_destroy_read_struct(&m_png, &m_info, nullptr); }
    PngStream(const PngStream&) = delete;
    PngStream& operator=(const PngStream&) = delete;

    // Reads the header and sets up the transforms for `target`; layout() is valid afterwards.
    Status readInfo(PngTarget target);
    // Decodes every row, handing each finished row (top to bottom) to `sink`.
    Status readRows(const std::function<void(const unsigned char* row, int64_t y)>& sink);

    int64_t width() const { return png_get_image_width(m_png, m_info); }
    // The row buffer of readRows: every row of an interlaced image (its passes refine all of it).
    int64_t bufferBytes() const {
        const bool interlaced = png_get_interlace_type(m_png, m_info) != PNG_INTERLACE_NONE;
        return int64_t(png_get_rowbytes(m_png, m_info)) * (interlaced ? height() : 1);
    }
    int64_t height() const { return png_get_image_height(m_png, m_info); }
    PixelLayout layout() const {
        return {png_get_bit_depth(m_png, m_info) == 16 ? Scalar::U16 : Scalar::U8,
                std::endian::big, png_get_channels(m_png, m_info)};
    }

private:
    static void onError(png_structp png, png_const_charp message);
    static void onWarning(png_structp, png_const_charp) {}  // benign: the image still decodes
    static void onRead(png_structp png, png_bytep data, size_t length);
    void setTransforms(PngTarget target);
    Status checkDataSize(PngTarget target) const;
    Error failure() const;
    Error headerFailure() const;

    FileReader& m_file;
    int64_t m_maxSamples;
    png_structp m_png = nullptr;
    png_infop m_info = nullptr;
    char m_message[256] = "";
    bool m_truncated = false;
    int64_t m_idatBytes = 0;
    int64_t m_fileBits = 0;
};

// libpng allocates (and clears) an ancillary chunk's declared length before reading it, so one
// damaged length field makes a file of a hundred bytes cost up to 2 GB. A chunk that runs past
// the end of the file means a truncated file: the chunk lengths are walked before libpng starts.
// The same walk adds up the IDAT lengths: the compressed image data (see checkDataSize).
bool chunksFitInFile(FileReader& file, int64_t& idatBytes) {
    int64_t pos = 8;  // after the signature
    unsigned char header[8];
    idatBytes = 0;
    while (file.seek(pos) && file.read(header, sizeof header)) {
        const int64_t length = int64_t(header[0]) << 24 | header[1] << 16 | header[2] << 8 |
                               header[3];
        pos += 12 + length;  // length, type, data, CRC
        if (pos > file.size()) return false;
        if (std::memcmp(header + 4, "IDAT", 4) == 0) idatBytes += length;
        if (std::memcmp(header + 4, "IEND", 4) == 0) break;
    }
    return file.seek(0);
}

void PngStream::onError(png_structp png, png_const_charp message) {
    auto* self = static_cast<PngStream*>(png_get_error_ptr(png));
    std::snprintf(self->m_message, sizeof self->m_message, "%s", message);
    png_longjmp(png, 1);
}

void PngStream::onRead(png_structp png, png_bytep data, size_t length) {
    auto* self = static_cast<PngStream*>(png_get_io_ptr(png));
    if (!self->m_file.read(data, length)) {
        self->m_truncated = true;
        png_error(png, "unexpected end of file");
    }
}

Error PngStream::failure() const {
    if (m_truncated)
        return makeError(ErrorKind::InvalidInput, "{}: truncated PNG (the file ends early)",
                         m_file.path());
    return makeError(ErrorKind::InvalidInput, "{}: corrupt PNG: {}", m_file.path(), m_message);
}

// libpng refuses sizes over its user limits with a generic message; state the limit instead.
Error PngStream::headerFailure() const {
    const auto head = m_file.head();
    const bool hasIhdr = head.size() >= 24 && std::memcmp(head.data() + 12, "IHDR", 4) == 0;
    auto be32 = [&](size_t at) {
        return int64_t(head[at]) << 24 | int64_t(head[at + 1]) << 16 | head[at + 2] << 8 |
               head[at + 3];
    };
    if (hasIhdr) {
        if (Status s = checkDimensions(m_file.path(), be32(16), be32(20), m_maxSamples); !s)
            return s.error();
    }
    return failure();
}

void PngStream::setTransforms(PngTarget target) {
    png_set_palette_to_rgb(m_png);
    png_set_expand_gray_1_2_4_to_8(m_png);
    if (target == PngTarget::Height) {
        png_set_tRNS_to_alpha(m_png);  // so that --channel a sees transparency
    } else {
        png_set_gray_to_rgb(m_png);
        png_set_scale_16(m_png);
        png_set_strip_alpha(m_png);
    }
}

Status PngStream::readInfo(PngTarget target) {
    if (!m_png || !m_info)
        return makeError(ErrorKind::Runtime, "{}: cannot create a PNG reader", m_file.path());
    if (!chunksFitInFile(m_file, m_idatBytes)) {
        m_truncated = true;
        return failure();
    }
    if (setjmp(png_jmpbuf(m_png))) return headerFailure();
    png_set_read_fn(m_png, this, onRead);
    png_set_user_limits(m_png, kMaxDimension, kMaxDimension);
    png_set_chunk_malloc_max(m_png, 8 << 20);  // ancillary chunks (text, profiles) stay small
    png_read_info(m_png, m_info);
    // The bits per pixel stored in the file (a palette index, not the RGB it expands to).
    m_fileBits = int64_t(png_get_bit_depth(m_png, m_info)) * png_get_channels(m_png, m_info);
    setTransforms(target);
    png_set_interlace_handling(m_png);
    png_read_update_info(m_png, m_info);
    return checkDataSize(target);
}

// Deflate expands at most 1032:1 (zlib's documented limit), so image data shorter than the
// pixels' bits over that ratio cannot be a whole image: a header that claims 16384x16384 in a
// file of 69 bytes is refused here, before its buffers are allocated, with what they would cost.
Status PngStream::checkDataSize(PngTarget target) const {
    // The sample limit speaks first, as it did before this check existed.
    if (Status s = checkDimensions(m_file.path(), width(), height(), m_maxSamples); !s) return s;
    const int64_t bits = m_fileBits;
    const int64_t decoded = width() * height() * bits / 8;
    constexpr int64_t kMaxRatio = 1032, kSlack = 4096;  // slack: zlib and block headers
    if (m_idatBytes * kMaxRatio + kSlack >= decoded) return {};
    const int64_t memory = bufferBytes() + width() * height() * (target == PngTarget::Height ? 4 : 3);
    return makeError(ErrorKind::InvalidInput,
                     "{}: corrupt PNG: {} bytes of compressed image data cannot hold {}x{} pixels "
                     "of {} bits (decoding would need about {})",
                     m_file.path(), m_idatBytes, width(), height(), bits, formatBytes(memory));
}

Status PngStream::readRows(const std::function<void(const unsigned char*, int64_t)>& sink) {
    const int64_t rows = height();
    const size_t stride = png_get_rowbytes(m_png, m_info);
    const bool interlaced = png_get_interlace_type(m_png, m_info) != PNG_INTERLACE_NONE;
    // Interlaced passes refine the whole image, so they need it all; otherwise one row suffices.
    std::vector<unsigned char> buffer(stride * size_t(interlaced ? rows : 1));
    const int passes = interlaced ? PNG_INTERLACE_ADAM7_PASSES : 1;
    if (setjmp(png_jmpbuf(m_png))) return failure();
    for (int pass = 0; pass < passes; ++pass) {
        for (int64_t y = 0; y < rows; ++y) {
            unsigned char* row = buffer.data() + (interlaced ? size_t(y) * stride : 0);
            png_read_row(m_png, row, nullptr);
            if (pass == passes - 1) sink(row, y);
        }
    }
    png_read_end(m_png, nullptr);  // checks the rest of the stream (last CRC, IEND)
    return {};
}

class PngHeightDecoder final : public HeightDecoder {
public:
    PngHeightDecoder(FileReader& file, ChannelSelect select, int64_t maxSamples)
        : m_stream(file, maxSamples), m_path(file.path()), m_select(select) {}

    Result<ImageHeader> readHeader() override {
        if (Status s = m_stream.readInfo(PngTarget::Height); !s) return s.error();
        if (Status s = checkChannel(m_path, m_stream.layout().channels, m_select); !s)
            return s.error();
        return ImageHeader{m_stream.width(), m_stream.height(), false};
    }

    int64_t scratchBytes() const override { return m_stream.bufferBytes(); }

    Status readPixels(std::span<float> pixels) override {
        const PixelLayout layout = m_stream.layout();
        const int64_t width = m_stream.width();
        return m_stream.readRows([&](const unsigned char* row, int64_t y) {
            convertRow(row, layout, width, m_select, pixels.data() + y * width);
        });
    }

private:
    PngStream m_stream;
    std::string m_path;
    ChannelSelect m_select;
};

class PngColorDecoder final : public ColorDecoder {
public:
    PngColorDecoder(FileReader& file, int64_t maxSamples)
        : m_stream(file, maxSamples), m_path(file.path()) {}

    Result<ImageHeader> readHeader() override {
        if (Status s = m_stream.readInfo(PngTarget::Color); !s) return s.error();
        const PixelLayout layout = m_stream.layout();
        if (layout.channels != 3 || layout.scalar != Scalar::U8)
            return makeError(ErrorKind::Unsupported, "{}: PNG layout not reducible to 8-bit RGB",
                             m_path);
        return ImageHeader{m_stream.width(), m_stream.height(), false};
    }

    int64_t scratchBytes() const override { return m_stream.bufferBytes(); }

    Status readPixels(std::span<Rgb8> pixels) override {
        const int64_t width = m_stream.width();
        return m_stream.readRows([&](const unsigned char* row, int64_t y) {
            std::memcpy(pixels.data() + y * width, row, size_t(width) * sizeof(Rgb8));
        });
    }

private:
    PngStream m_stream;
    std::string m_path;
};

}  // namespace

std::unique_ptr<HeightDecoder> makePngHeightDecoder(FileReader& file, ChannelSelect select,
                                                    int64_t maxSamples) {
    return std::make_unique<PngHeightDecoder>(file, select, maxSamples);
}

std::unique_ptr<ColorDecoder> makePngColorDecoder(FileReader& file, int64_t maxSamples) {
    return std::make_unique<PngColorDecoder>(file, maxSamples);
}

}  // namespace relief
