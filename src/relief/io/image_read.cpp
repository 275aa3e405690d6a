// The file readers' entry points: open the file, choose the reader from its content (never its
// extension) and run the shared flow of read_common.h. One reader per format in <format>_read.cpp.
#include <relief/io/read_common.h>

#include <exception>

namespace relief {

namespace {

Error unrecognized(const std::string& path) {
    return makeError(ErrorKind::InvalidInput,
                     "{}: not a PNG/JPEG/EXR/PFM file (unrecognized header); headerless samples "
                     "need --raw WxH:u8|u16|f32",
                     path);
}

// The library never throws: OpenEXR is caught where it is used; this catches the rest.
template <class Body>
auto withoutExceptions(const std::string& path, Body&& body) -> decltype(body()) {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        return makeError(ErrorKind::Runtime, "{}: out of memory while reading", path);
    } catch (const std::exception& e) {
        return makeError(ErrorKind::Runtime, "{}: {}", path, e.what());
    }
}

Result<std::unique_ptr<HeightDecoder>> makeHeightDecoder(FileReader& file,
                                                         const LoadOptions& options) {
    if (options.raw) return makeRawHeightDecoder(file, *options.raw);
    switch (detectFormat(file.head())) {
        case FileFormat::Png:
            return makePngHeightDecoder(file, options.channel, options.maxSamples);
        case FileFormat::Jpeg: return makeJpegHeightDecoder(file, options.channel);
        case FileFormat::Exr: return makeExrHeightDecoder(file, options.channel);
        case FileFormat::Pfm: return makePfmHeightDecoder(file, options.channel);
        case FileFormat::Unknown: break;
    }
    return unrecognized(file.path());
}

Result<std::unique_ptr<ColorDecoder>> makeColorDecoder(FileReader& file, int64_t maxSamples) {
    switch (detectFormat(file.head())) {
        case FileFormat::Png: return makePngColorDecoder(file, maxSamples);
        case FileFormat::Jpeg: return makeJpegColorDecoder(file);
        case FileFormat::Exr:
        case FileFormat::Pfm:
            return makeError(ErrorKind::Unsupported, "{}: colour images must be PNG or JPEG",
                             file.path());
        case FileFormat::Unknown: break;
    }
    return unrecognized(file.path());
}

// Integer codes are already in [0,1]; float values are rescaled by the file's range or the
// user's (DESIGN §1), which means nothing for integer codes and is refused for them.
Result<Heightfield> toHeightfield(Decoded<float> decoded, const std::string& path,
                                  const LoadOptions& options) {
    if (!decoded.header.isFloat && (options.rangeLo || options.rangeHi))
        return makeError(ErrorKind::BadArgument,
                         "--height-range applies to float data (EXR, PFM, raw f32); {} holds "
                         "integer codes, which are divided by their maximum",
                         path);
    Heightfield hf;
    hf.width = decoded.image.width;
    hf.height = decoded.image.height;
    hf.samples = std::move(decoded.image.pixels);
    if (decoded.header.isFloat) {
        if (Status s = normalizeSamples(path, hf.samples, hf.width, options.rangeLo.value_or(0.0),
                                        options.rangeHi.value_or(0.0));
            !s)
            return s.error();
    }
    return hf;
}

// The shared flow of the file and in-memory entry points, on an opened reader.
Result<Heightfield> readHeightfield(Result<FileReader> file, const LoadOptions& options) {
    if (!file) return file.error();
    const std::string path = file->path();
    return withoutExceptions(path, [&]() -> Result<Heightfield> {
        if (file->size() == 0) return makeError(ErrorKind::InvalidInput, "{}: empty file", path);
        auto decoder = makeHeightDecoder(*file, options);
        if (!decoder) return decoder.error();
        auto decoded = decodeImage(**decoder, path, options.maxSamples);
        if (!decoded) return decoded.error();
        return toHeightfield(std::move(*decoded), path, options);
    });
}

Result<ImageRgb8> readColorImage(Result<FileReader> file, int64_t maxSamples) {
    if (!file) return file.error();
    const std::string path = file->path();
    return withoutExceptions(path, [&]() -> Result<ImageRgb8> {
        if (file->size() == 0) return makeError(ErrorKind::InvalidInput, "{}: empty file", path);
        auto decoder = makeColorDecoder(*file, maxSamples);
        if (!decoder) return decoder.error();
        auto decoded = decodeImage(**decoder, path, maxSamples);
        if (!decoded) return decoded.error();
        return std::move(decoded->image);
    });
}

}  // namespace

Result<Heightfield> loadHeightfieldFile(const std::string& path, const LoadOptions& options) {
    return readHeightfield(FileReader::open(path), options);
}

Result<ImageRgb8> loadColorImage(const std::string& path) {
    return readColorImage(FileReader::open(path), kDefaultMaxSamples);
}

Result<Heightfield> decodeHeightfield(std::span<const unsigned char> bytes,
                                      const std::string& name, const LoadOptions& options) {
    return readHeightfield(FileReader::fromMemory(bytes, name), options);
}

Result<ImageRgb8> decodeColorImage(std::span<const unsigned char> bytes, const std::string& name,
                                   int64_t maxSamples) {
    return readColorImage(FileReader::fromMemory(bytes, name), maxSamples);
}

}  // namespace relief
