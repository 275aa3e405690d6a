#pragma once
// What the image readers share (internal to src/relief/io): the opened file, format detection,
// pixel-row conversion and the one flow every reader follows: read the header, check the size,
// allocate, fill. The public entry points are in heightfield_io.h.
#include <relief/core/heightfield.h>
#include <relief/core/image.h>
#include <relief/core/memory_budget.h>
#include <relief/io/heightfield_io.h>

#include <array>
#include <bit>
#include <cstdio>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace relief {

// Every input file is opened here: open(2) with O_NONBLOCK (a FIFO without a writer would block
// in open itself), then its type checked before a byte is read. `what` names the expected content
// in messages ("an image file", "a ray file"). The stream returned blocks again as usual.
struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;
Result<FilePtr> openRegularFile(const std::string& path, std::string_view what,
                                int64_t* size = nullptr);

// An opened regular file with its size and its first bytes (enough for every format's magic and
// a PFM header). The read position starts at 0.
class FileReader {
public:
    static Result<FileReader> open(const std::string& path);
    // Bytes in memory read as a file named `name` (in messages); they must outlive the reader.
    static Result<FileReader> fromMemory(std::span<const unsigned char> bytes, std::string name);

    const std::string& path() const { return m_path; }
    int64_t size() const { return m_size; }
    std::span<const unsigned char> head() const { return {m_head.data(), m_headSize}; }

    bool read(void* data, size_t bytes);  // false on a short read
    bool seek(int64_t offset);
    int64_t tell();
    Result<std::vector<unsigned char>> readAll();

private:
    void readHead();

    std::string m_path;
    FilePtr m_file;
    int64_t m_size = 0;
    std::array<unsigned char, 128> m_head{};
    size_t m_headSize = 0;
};

enum class FileFormat { Png, Jpeg, Exr, Pfm, Unknown };
FileFormat detectFormat(std::span<const unsigned char> head);

// The layout of one decoded pixel row. Channels: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA.
enum class Scalar { U8, U16, F32 };
struct PixelLayout {
    Scalar scalar = Scalar::U8;
    std::endian endian = std::endian::native;
    int channels = 1;
};
size_t rowBytes(const PixelLayout& layout, int64_t width);
// Bytes of a whole image, or -1 when a side lies outside [1, kMaxDimension] (where the product
// could overflow; checkDimensions reports those sizes).
int64_t imageBytes(const PixelLayout& layout, int64_t width, int64_t height);

// Refuses a channel the image lacks (only alpha can be missing: grey stands for R, G and B).
Status checkChannel(const std::string& path, int channels, ChannelSelect select);

// One row of pixels → heights: integer codes divided by their maximum (DESIGN §1), floats as they
// are, colour reduced to Rec. 709 luminance or the selected channel.
void convertRow(const unsigned char* row, const PixelLayout& layout, int64_t width,
                ChannelSelect select, float* out);

// Reads `rows` rows of `layout` pixels from the file's current position into heights, in file
// order or (bottomUp) with the first file row stored last.
Status readRows(FileReader& file, const PixelLayout& layout, ChannelSelect select, bool bottomUp,
                int64_t width, std::span<float> out);

struct ImageHeader {
    int64_t width = 0;
    int64_t height = 0;
    bool isFloat = false;  // raw values, normalized later by range (DESIGN §1)
};

// A reader in two steps, so that the size is checked before any pixel storage is allocated.
template <class T>
class Decoder {
public:
    virtual ~Decoder() = default;
    virtual Result<ImageHeader> readHeader() = 0;
    virtual Status readPixels(std::span<T> pixels) = 0;  // row-major, row 0 at the top
    // Bytes the decoder holds besides the output while decoding (valid after readHeader): an
    // interlaced PNG's whole image, a JPEG's decoded pixels. Counted against the memory budget.
    virtual int64_t scratchBytes() const { return 0; }
};
using HeightDecoder = Decoder<float>;
using ColorDecoder = Decoder<Rgb8>;

template <class T>
struct Decoded {
    ImageHeader header;
    Image<T> image;
};

template <class T>
Result<Decoded<T>> decodeImage(Decoder<T>& decoder, const std::string& path, int64_t maxSamples) {
    auto header = decoder.readHeader();
    if (!header) return header.error();
    if (Status s = checkDimensions(path, header->width, header->height, maxSamples); !s)
        return s.error();
    const int64_t bytes = header->width * header->height * int64_t(sizeof(T)) + decoder.scratchBytes();
    if (Status s = reserveMemory(bytes, fmt::format("{}: decoding {}x{} pixels", path, header->width,
                                                     header->height));
        !s)
        return s.error();
    Decoded<T> decoded{*header, Image<T>(int(header->width), int(header->height))};
    if (Status s = decoder.readPixels(decoded.image.pixels); !s) return s.error();
    return decoded;
}

// One factory per format; each reader lives in its own <format>_read.cpp.
std::unique_ptr<HeightDecoder> makePngHeightDecoder(FileReader& file, ChannelSelect select,
                                                    int64_t maxSamples);
std::unique_ptr<ColorDecoder> makePngColorDecoder(FileReader& file, int64_t maxSamples);
std::unique_ptr<HeightDecoder> makeJpegHeightDecoder(FileReader& file, ChannelSelect select);
std::unique_ptr<ColorDecoder> makeJpegColorDecoder(FileReader& file);
std::unique_ptr<HeightDecoder> makeExrHeightDecoder(FileReader& file, ChannelSelect select);
std::unique_ptr<HeightDecoder> makePfmHeightDecoder(FileReader& file, ChannelSelect select);
std::unique_ptr<HeightDecoder> makeRawHeightDecoder(FileReader& file, const RawLayout& layout);

// Declared here for heightfield_io.cpp, which dispatches files and generators.
Result<Heightfield> loadHeightfieldFile(const std::string& path, const LoadOptions& options);

}  // namespace relief
