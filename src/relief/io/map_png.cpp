// Maps as PNG (docs/maps.md): one array per file, 8 or 16 bits, grey (1 channel), grey + alpha
// (2: channel 0 in grey, channel 1 in alpha), RGB (3) or RGBA (4); the relief keys of
// map_container.h in tEXt chunks before the image data. Codes are UNORM (value = code / (2^b − 1))
// or, for integer arrays, the values themselves ("relief.storage"). libpng reports errors by
// longjmp: the functions that call setjmp hold no objects a jump could skip.
#include <relief/io/image_write.h>
#include <relief/io/map_container.h>

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace relief {

namespace {

struct PngState {
    std::string message;
    std::vector<unsigned char>* out = nullptr;
    std::span<const unsigned char> in;
    size_t position = 0;
};

extern "C" void mapPngError(png_structp png, png_const_charp message) {
    static_cast<PngState*>(png_get_error_ptr(png))->message = message ? message : "";
    png_longjmp(png, 1);
}
extern "C" void mapPngWarning(png_structp, png_const_charp) {}
extern "C" void mapPngWrite(png_structp png, png_bytep data, size_t length) {
    auto* state = static_cast<PngState*>(png_get_io_ptr(png));
    state->out->insert(state->out->end(), data, data + length);
}
extern "C" void mapPngFlush(png_structp) {}
extern "C" void mapPngRead(png_structp png, png_bytep data, size_t length) {
    auto* state = static_cast<PngState*>(png_get_io_ptr(png));
    if (state->in.size() - state->position < length) png_error(png, "unexpected end of file");
    std::memcpy(data, state->in.data() + state->position, length);
    state->position += length;
}

int colorType(int channels) {
    switch (channels) {
        case 1: return PNG_COLOR_TYPE_GRAY;
        case 2: return PNG_COLOR_TYPE_GRAY_ALPHA;
        case 3: return PNG_COLOR_TYPE_RGB;
        default: return PNG_COLOR_TYPE_RGBA;
    }
}

// Big-endian codes, row-major, channels interleaved: what libpng takes and gives.
std::vector<unsigned char> packCodes(const MapArray& a, MapStorage storage) {
    const int bytes = storageBits(storage) / 8;
    std::vector<unsigned char> out(a.data.size() * size_t(bytes));
    for (size_t k = 0; k < a.data.size(); ++k) {
        const uint32_t code = encodeCode(storage, a.data[k]);
        if (bytes == 2) {
            out[2 * k] = (unsigned char)(code >> 8);
            out[2 * k + 1] = (unsigned char)code;
        } else {
            out[k] = (unsigned char)code;
        }
    }
    return out;
}

std::vector<png_text> textChunks(const std::vector<std::pair<std::string, std::string>>& keys) {
    std::vector<png_text> text(keys.size());
    for (size_t k = 0; k < keys.size(); ++k) {
        text[k].compression = PNG_TEXT_COMPRESSION_NONE;
        text[k].key = const_cast<char*>(keys[k].first.c_str());
        text[k].text = const_cast<char*>(keys[k].second.c_str());
        text[k].text_length = keys[k].second.size();
    }
    return text;
}

// Everything with a destructor lives in the caller: libpng's longjmp skips none.
bool encodePng(const MapArray& a, MapStorage storage, png_text* text, int textCount,
               const std::vector<unsigned char>& codes, PngState& state) {
    const size_t stride = size_t(a.width) * size_t(a.channels) * size_t(storageBits(storage) / 8);
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, mapPngError, mapPngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &state, mapPngWrite, mapPngFlush);
    png_set_IHDR(png, info, png_uint_32(a.width), png_uint_32(a.height), storageBits(storage),
                 colorType(a.channels), PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_text(png, info, text, textCount);
    png_write_info(png, info);
    for (int y = 0; y < a.height; ++y) png_write_row(png, codes.data() + size_t(y) * stride);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace

Status writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
    return writeAtomically(path, [&](const std::string& temp) -> Status {
        std::FILE* file = std::fopen(temp.c_str(), "wb");
        if (!file)
            return makeError(ErrorKind::Io, "{}: cannot open for writing: {}", path,
                             std::strerror(errno));
        const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
        const bool failed = std::ferror(file) != 0;
        if (std::fclose(file) != 0 || failed || !written)
            return makeError(ErrorKind::Io, "{}: write failed: {}", path, std::strerror(errno));
        return {};
    });
}

Status writePngMaps(const std::string& path, const MapFile& maps,
                    std::span<const MapStorage> storages) {
    const TechniqueMaps& t = maps.techniques.front();
    if (t.arrays.size() != 1)
        return makeError(ErrorKind::BadArgument,
                         "{}: {} maps are {} arrays ({}, ...) and a PNG holds one: write "
                         "--format ktx2 (one file) or --format exr",
                         path, t.technique, t.arrays.size(), t.arrays.front().name);
    const MapArray& a = t.arrays.front();
    const MapStorage storage = storages.front();
    if (storage == MapStorage::Float32 || a.channels > 4)
        return makeError(ErrorKind::BadArgument,
                         "{}: {}/{} holds 32-bit floats and a PNG holds 8/16-bit codes: write "
                         "--format ktx2 or exr",
                         path, t.technique, a.name);
    PngState state;
    std::vector<unsigned char> bytes;
    state.out = &bytes;
    const std::vector<unsigned char> codes = packCodes(a, storage);
    const auto keys = containerKeys(maps, storage);
    std::vector<png_text> text = textChunks(keys);
    if (!encodePng(a, storage, text.data(), int(text.size()), codes, state))
        return makeError(ErrorKind::Runtime, "{}: PNG encoding failed: {}", path, state.message);
    return writeBytes(path, bytes);
}

namespace {

struct PngImage {
    int width = 0, height = 0, bits = 0, channels = 0;
    std::map<std::string, std::string> text;
    std::vector<unsigned char> pixels;  // big-endian codes
};

// The header and text first (no pixel buffer before the size is checked), then the rows.
bool decodePng(PngState& state, PngImage& image, std::string& problem) {
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, mapPngError, mapPngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_set_read_fn(png, &state, mapPngRead);
    png_set_user_limits(png, kMaxDimension, kMaxDimension);
    png_set_chunk_malloc_max(png, 1 << 20);  // text chunks stay small
    png_read_info(png, info);
    image.width = int(png_get_image_width(png, info));
    image.height = int(png_get_image_height(png, info));
    image.bits = png_get_bit_depth(png, info);
    const int type = png_get_color_type(png, info);
    image.channels = type == PNG_COLOR_TYPE_GRAY         ? 1
                     : type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                     : type == PNG_COLOR_TYPE_RGB        ? 3
                     : type == PNG_COLOR_TYPE_RGBA       ? 4
                                                         : 0;
    png_textp text = nullptr;
    int count = 0;
    png_get_text(png, info, &text, &count);
    for (int k = 0; k < count; ++k)
        image.text[text[k].key] = std::string(text[k].text, text[k].text_length);
    const int64_t samples = int64_t(image.width) * image.height * std::max(1, image.channels);
    // Deflate expands at most 1032:1: a file far smaller than its pixels cannot hold them.
    const int64_t bytes = samples * std::max(1, image.bits / 8);
    if (image.channels == 0 || (image.bits != 8 && image.bits != 16) ||
        png_get_interlace_type(png, info) != PNG_INTERLACE_NONE) {
        problem = "not an 8/16-bit grey, grey+alpha, RGB or RGBA non-interlaced PNG";
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    if (samples > kDefaultMaxSamples || bytes > int64_t(state.in.size()) * 1032 + 4096) {
        problem = fmt::format("{}x{} pixels cannot be in a file of {} bytes or exceed the size "
                              "limit", image.width, image.height, state.in.size());
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    const size_t stride = png_get_rowbytes(png, info);
    image.pixels.resize(stride * size_t(image.height));
    for (int y = 0; y < image.height; ++y)
        png_read_row(png, image.pixels.data() + size_t(y) * stride, nullptr);
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

}  // namespace

Result<MapFile> readPngMaps(FileReader& file) {
    const std::string path = file.path();
    auto bytes = file.readAll();
    if (!bytes) return bytes.error();
    PngState state;
    state.in = *bytes;
    PngImage image;
    std::string problem;
    if (!decodePng(state, image, problem))
        return makeError(ErrorKind::InvalidInput, "{}: corrupt PNG map file: {}", path,
                         state.message);
    auto keys = parseContainerKeys(path, image.text);
    if (!keys) return keys.error();
    if (!problem.empty() && keys->common)
        return makeError(ErrorKind::InvalidInput, "{}: map file damaged: {}", path, problem);
    if (keys->common && keys->arrays.size() != 1)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: a PNG holds one array, its keys list {}", path,
                         keys->arrays.size());
    return assembleMaps(path, *keys, [&](size_t) -> Result<MapArray> {
        const ContainerArray& want = keys->arrays.front();
        const int bits = storageBits(keys->storage);
        if (keys->storage == MapStorage::Float32 || image.bits != bits ||
            image.channels != want.channels || image.width != want.width ||
            image.height != want.height)
            return makeError(ErrorKind::InvalidInput,
                             "{}: map file damaged: the image is {}x{}, {} channels of {} bits, "
                             "its keys say {}x{}x{} stored as {}",
                             path, image.width, image.height, image.channels, image.bits,
                             want.width, want.height, want.channels, storageName(keys->storage));
        MapArray a{want.name, want.width, want.height, want.channels, {}};
        const size_t count = size_t(a.width) * size_t(a.height) * size_t(a.channels);
        a.data.resize(count);
        for (size_t k = 0; k < count; ++k) {
            const uint32_t code = bits == 16 ? uint32_t(image.pixels[2 * k]) << 8 | image.pixels[2 * k + 1]
                                             : image.pixels[k];
            a.data[k] = decodeCode(keys->storage, code);
        }
        return a;
    });
}

}  // namespace relief
