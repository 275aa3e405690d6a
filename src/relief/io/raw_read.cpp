// Headerless little-endian samples, described by --raw WxH:u8|u16|f32. With no header to check,
// the file size is the only evidence that the layout is right, so it must match exactly.
#include <relief/io/read_common.h>

namespace relief {

namespace {

const char* typeName(RawLayout::Type type) {
    switch (type) {
        case RawLayout::Type::U8: return "u8";
        case RawLayout::Type::U16: return "u16";
        case RawLayout::Type::F32: return "f32";
    }
    return "?";
}

Scalar scalarOf(RawLayout::Type type) {
    switch (type) {
        case RawLayout::Type::U8: return Scalar::U8;
        case RawLayout::Type::U16: return Scalar::U16;
        case RawLayout::Type::F32: return Scalar::F32;
    }
    return Scalar::U8;
}

class RawHeightDecoder final : public HeightDecoder {
public:
    RawHeightDecoder(FileReader& file, const RawLayout& raw)
        : m_file(file), m_raw(raw), m_layout{scalarOf(raw.type), std::endian::little, 1} {}

    Result<ImageHeader> readHeader() override {
        const int64_t needed = imageBytes(m_layout, m_raw.width, m_raw.height);
        if (needed >= 0 && needed != m_file.size())
            return makeError(ErrorKind::InvalidInput,
                             "{}: raw {}x{}:{} needs exactly {} bytes but the file has {} bytes",
                             m_file.path(), m_raw.width, m_raw.height, typeName(m_raw.type),
                             needed, m_file.size());
        return ImageHeader{m_raw.width, m_raw.height, m_raw.type == RawLayout::Type::F32};
    }

    Status readPixels(std::span<float> pixels) override {
        return readRows(m_file, m_layout, ChannelSelect::Luminance, false, m_raw.width, pixels);
    }

private:
    FileReader& m_file;
    RawLayout m_raw;
    PixelLayout m_layout;
};

}  // namespace

std::unique_ptr<HeightDecoder> makeRawHeightDecoder(FileReader& file, const RawLayout& layout) {
    return std::make_unique<RawHeightDecoder>(file, layout);
}

}  // namespace relief
