// The file readers (src/relief/io/*_read.cpp): exact values per format, then hostile files, each
// of which must come back as an error of the right kind with a message that says what is wrong.
#include <relief/io/heightfield_io.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <gtest/gtest.h>
#include <half.h>
#include <png.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

namespace relief {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

// ---------------------------------------------------------------------------------------------
// Writing test files

Bytes readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void appendBe32(Bytes& bytes, uint32_t value) {
    for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back((value >> shift) & 0xff);
}

Bytes be16(const std::vector<uint16_t>& values) {
    Bytes bytes;
    for (uint16_t v : values) bytes.insert(bytes.end(), {uint8_t(v >> 8), uint8_t(v & 0xff)});
    return bytes;
}

struct PngSpec {
    PngSpec(int w, int h, int type = PNG_COLOR_TYPE_GRAY, int depth = 8, bool adam7 = false,
            std::vector<png_color> colours = {})
        : width(w), height(h), colorType(type), bitDepth(depth), interlaced(adam7),
          palette(std::move(colours)) {}
    int width, height;
    int colorType;
    int bitDepth;
    bool interlaced;
    std::vector<png_color> palette;
};

// `rows`: packed scanlines as PNG stores them (16-bit samples big endian).
void writePng(const fs::path& path, const PngSpec& spec, const Bytes& rows) {
    const size_t stride = rows.size() / size_t(spec.height);
    std::vector<png_bytep> pointers;  // before setjmp: nothing to destroy on libpng's longjmp
    for (int y = 0; y < spec.height; ++y)
        pointers.push_back(const_cast<png_bytep>(rows.data() + size_t(y) * stride));
    FILE* file = std::fopen(path.c_str(), "wb");
    ASSERT_NE(file, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    ASSERT_FALSE(setjmp(png_jmpbuf(png)));
    png_init_io(png, file);
    png_set_IHDR(png, info, spec.width, spec.height, spec.bitDepth, spec.colorType,
                 spec.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (!spec.palette.empty())
        png_set_PLTE(png, info, spec.palette.data(), int(spec.palette.size()));
    png_write_info(png, info);
    png_write_image(png, pointers.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
}

void writeExr(const fs::path& path, const Imath::Box2i& window,
              const std::vector<std::pair<std::string, std::vector<float>>>& channels,
              Imf::PixelType type = Imf::FLOAT) {
    const int64_t width = int64_t(window.max.x) - window.min.x + 1;
    Imf::Header header(window, window);
    std::vector<std::vector<half>> halves;
    Imf::FrameBuffer frame;
    for (const auto& [name, values] : channels) {
        header.channels().insert(name, Imf::Channel(type));
        const void* data = values.data();
        size_t stride = sizeof(float);
        if (type == Imf::HALF) {
            halves.emplace_back(values.begin(), values.end());
            data = halves.back().data();
            stride = sizeof(half);
        }
        frame.insert(name, Imf::Slice::Make(type, data, window, stride, stride * width));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(window.max.y - window.min.y + 1);
}

void writeExr(const fs::path& path, int width, int height, const std::vector<float>& y) {
    writeExr(path, Imath::Box2i({0, 0}, {width - 1, height - 1}), {{"Y", y}});
}

// `pixels`: top row first, `channels` floats per pixel; the file stores the bottom row first.
void writePfm(const fs::path& path, int width, int height, int channels,
              const std::vector<float>& pixels, std::endian endian) {
    const std::string header = fmt::format("{}\n{} {}\n{}\n", channels == 3 ? "PF" : "Pf", width,
                                           height, endian == std::endian::little ? -1.0 : 1.0);
    Bytes bytes(header.begin(), header.end());
    for (int y = height - 1; y >= 0; --y) {
        for (int k = 0; k < width * channels; ++k) {
            const uint32_t bits = std::bit_cast<uint32_t>(pixels[size_t(y * width * channels + k)]);
            for (int b = 0; b < 4; ++b)
                bytes.push_back(bits >> (8 * (endian == std::endian::little ? b : 3 - b)) & 0xff);
        }
    }
    writeBytes(path, bytes);
}

template <class T>
Bytes littleEndian(const std::vector<T>& values) {
    Bytes bytes;
    for (T v : values) {
        const auto bits = std::bit_cast<std::conditional_t<sizeof(T) == 4, uint32_t, T>>(v);
        for (size_t b = 0; b < sizeof(T); ++b) bytes.push_back((bits >> (8 * b)) & 0xff);
    }
    return bytes;
}

// A PNG chunk with its CRC, so that a crafted header gets past libpng's CRC check.
void appendChunk(Bytes& png, const char* type, const Bytes& data) {
    appendBe32(png, uint32_t(data.size()));
    Bytes typed(type, type + 4);
    typed.insert(typed.end(), data.begin(), data.end());
    png.insert(png.end(), typed.begin(), typed.end());
    appendBe32(png, uint32_t(crc32(0, typed.data(), uInt(typed.size()))));
}

// A PNG whose IHDR claims width×height, followed by a token IDAT: nothing to decode behind it.
Bytes pngClaiming(uint32_t width, uint32_t height) {
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    Bytes ihdr;
    appendBe32(ihdr, width);
    appendBe32(ihdr, height);
    ihdr.insert(ihdr.end(), {8, 0, 0, 0, 0});  // 8-bit grey
    appendChunk(png, "IHDR", ihdr);
    appendChunk(png, "IDAT", {0x78, 0x9c, 0x03, 0x00});
    appendChunk(png, "IEND", {});
    return png;
}

// Where `what` starts in `bytes`; 0 (after a test failure) if it is absent, so edits stay in bounds.
size_t find(const Bytes& bytes, std::string_view what) {
    auto it = std::search(bytes.begin(), bytes.end(), what.begin(), what.end(),
                          [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); });
    EXPECT_NE(it, bytes.end()) << what;
    return it == bytes.end() ? 0 : size_t(it - bytes.begin());
}

// ---------------------------------------------------------------------------------------------
// Fixture: a fresh folder per test

class IoTest : public ::testing::Test {
public:
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    std::string withBytes(const std::string& name, const Bytes& bytes) const {
        writeBytes(path(name), bytes);
        return path(name);
    }

    // An 8-bit grey PNG with distinct values, the valid file that hostile cases cut up.
    std::string validPng(int width = 64, int height = 48) const {
        Bytes rows;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) rows.push_back(uint8_t((x * 7 + y * 13) & 0xff));
        writePng(path("valid.png"), {width, height}, rows);
        return path("valid.png");
    }

protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = fmt::format("relief-io-{}-{}-{}", info->test_suite_name(),
                                       info->name(), std::random_device{}());
        std::replace(name.begin(), name.end(), '/', '_');  // parameterized names contain '/'
        m_dir = fs::temp_directory_path() / name;
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

private:
    fs::path m_dir;
};

std::string sourceFile(const std::string& relative) {
    return std::string(RELIEF_SOURCE_DIR) + "/" + relative;
}

// ---------------------------------------------------------------------------------------------
// PNG

using IoPng = IoTest;

TEST_F(IoPng, Grey8IsCodeOver255) {
    const Bytes codes = {0, 1, 127, 128, 254, 255};
    writePng(path("g8.png"), {3, 2}, codes);
    auto hf = loadHeightfield(path("g8.png"));
    ASSERT_TRUE(hf) << hf.error().message;
    ASSERT_EQ(hf->width, 3);
    ASSERT_EQ(hf->height, 2);
    for (size_t k = 0; k < codes.size(); ++k) EXPECT_EQ(hf->samples[k], float(codes[k]) / 255.0f);
}

TEST_F(IoPng, Grey16IsCodeOver65535) {
    const std::vector<uint16_t> codes = {0, 1, 12345, 32768, 65534, 65535};
    writePng(path("g16.png"), {2, 3, PNG_COLOR_TYPE_GRAY, 16}, be16(codes));
    auto hf = loadHeightfield(path("g16.png"));
    ASSERT_TRUE(hf) << hf.error().message;
    ASSERT_EQ(hf->width, 2);
    for (size_t k = 0; k < codes.size(); ++k)
        EXPECT_EQ(hf->samples[k], float(codes[k]) / 65535.0f);
}

TEST_F(IoPng, InvertIsAppliedOnce) {
    writePng(path("g8.png"), {2, 1}, {0, 51});
    LoadOptions options;
    options.invert = true;
    auto hf = loadHeightfield(path("g8.png"), options);
    ASSERT_TRUE(hf) << hf.error().message;
    EXPECT_FLOAT_EQ(hf->samples[0], 1.0f);
    EXPECT_FLOAT_EQ(hf->samples[1], 0.8f);
}

TEST_F(IoPng, RgbLuminanceAndChannelSelection) {
    const Bytes rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 200, 30};
    writePng(path("rgb.png"), {2, 2, PNG_COLOR_TYPE_RGB}, rgb);
    auto lum = loadHeightfield(path("rgb.png"));
    ASSERT_TRUE(lum) << lum.error().message;
    const float weights[] = {0.2126f, 0.7152f, 0.0722f};
    for (int k = 0; k < 4; ++k) {
        float expected = 0;
        for (int c = 0; c < 3; ++c) expected += weights[c] * float(rgb[size_t(k * 3 + c)]) / 255.0f;
        EXPECT_NEAR(lum->samples[size_t(k)], expected, 1e-6f) << "pixel " << k;
    }
    const ChannelSelect selects[] = {ChannelSelect::Red, ChannelSelect::Green, ChannelSelect::Blue};
    for (int c = 0; c < 3; ++c) {
        LoadOptions options;
        options.channel = selects[c];
        auto one = loadHeightfield(path("rgb.png"), options);
        ASSERT_TRUE(one) << one.error().message;
        for (int k = 0; k < 4; ++k)
            EXPECT_EQ(one->samples[size_t(k)], float(rgb[size_t(k * 3 + c)]) / 255.0f);
    }
}

TEST_F(IoPng, RgbaAlphaChannel) {
    const std::vector<uint16_t> rgba = {1, 2, 3, 65535, 4, 5, 6, 0, 7, 8, 9, 30000};
    writePng(path("rgba.png"), {3, 1, PNG_COLOR_TYPE_RGBA, 16}, be16(rgba));
    LoadOptions options;
    options.channel = ChannelSelect::Alpha;
    auto hf = loadHeightfield(path("rgba.png"), options);
    ASSERT_TRUE(hf) << hf.error().message;
    EXPECT_EQ(hf->samples[0], 1.0f);
    EXPECT_EQ(hf->samples[1], 0.0f);
    EXPECT_EQ(hf->samples[2], 30000.0f / 65535.0f);
}

TEST_F(IoPng, PaletteAndTwoBitGrey) {
    writePng(path("pal.png"), {2, 1, PNG_COLOR_TYPE_PALETTE, 8, false, {{0, 0, 0}, {0, 255, 0}}},
             {1, 0});
    auto pal = loadHeightfield(path("pal.png"));
    ASSERT_TRUE(pal) << pal.error().message;
    EXPECT_NEAR(pal->samples[0], 0.7152f, 1e-6f);
    EXPECT_EQ(pal->samples[1], 0.0f);

    writePng(path("g2.png"), {4, 1, PNG_COLOR_TYPE_GRAY, 2}, {0b00011011});  // codes 0 1 2 3
    auto g2 = loadHeightfield(path("g2.png"));
    ASSERT_TRUE(g2) << g2.error().message;
    for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(g2->samples[size_t(k)], float(k) / 3.0f);
}

TEST_F(IoPng, InterlacedMatchesValues) {
    Bytes codes;
    for (int k = 0; k < 11 * 9; ++k) codes.push_back(uint8_t(k * 3));
    writePng(path("adam7.png"), {11, 9, PNG_COLOR_TYPE_GRAY, 8, true}, codes);
    auto hf = loadHeightfield(path("adam7.png"));
    ASSERT_TRUE(hf) << hf.error().message;
    for (size_t k = 0; k < codes.size(); ++k) ASSERT_EQ(hf->samples[k], float(codes[k]) / 255.0f);
}

TEST_F(IoPng, RepositoryHeightmaps) {
    auto eight = loadHeightfield(sourceFile("data/colorado-elevation-400.png"));
    ASSERT_TRUE(eight) << eight.error().message;
    EXPECT_EQ(eight->width, 400);
    auto sixteen = loadHeightfield(sourceFile("data/finland-topography-400-16bit.png"));
    ASSERT_TRUE(sixteen) << sixteen.error().message;
    EXPECT_EQ(sixteen->height, 400);
    // 16-bit precision survives: some sample is not a multiple of 1/255.
    EXPECT_TRUE(std::any_of(sixteen->samples.begin(), sixteen->samples.end(), [](float v) {
        return std::abs(v * 255.0f - std::round(v * 255.0f)) > 1e-3f;
    }));
}

// ---------------------------------------------------------------------------------------------
// Colour images and JPEG

using IoColor = IoTest;

TEST_F(IoColor, PngRgbAndGrey16) {
    const Bytes rgb = {1, 2, 3, 250, 251, 252};
    writePng(path("rgb.png"), {2, 1, PNG_COLOR_TYPE_RGB}, rgb);
    auto image = loadColorImage(path("rgb.png"));
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->at(0, 0), Rgb8(1, 2, 3));
    EXPECT_EQ(image->at(1, 0), Rgb8(250, 251, 252));

    writePng(path("g16.png"), {2, 1, PNG_COLOR_TYPE_GRAY, 16}, be16({65535, 0x8080}));
    auto grey = loadColorImage(path("g16.png"));
    ASSERT_TRUE(grey) << grey.error().message;
    EXPECT_EQ(grey->at(0, 0), Rgb8(255, 255, 255));
    EXPECT_EQ(grey->at(1, 0), Rgb8(128, 128, 128));
}

TEST_F(IoColor, JpegColourAndHeightAgree) {
    const std::string jpeg = sourceFile("data/finland-map-600.jpg");
    auto image = loadColorImage(jpeg);
    ASSERT_TRUE(image) << image.error().message;
    auto hf = loadHeightfield(jpeg);
    ASSERT_TRUE(hf) << hf.error().message;
    ASSERT_EQ(hf->width, image->width);
    ASSERT_EQ(hf->height, image->height);
    EXPECT_EQ(hf->width, 600);
    for (int y = 0; y < hf->height; y += 37) {
        for (int x = 0; x < hf->width; x += 41) {
            const Rgb8 c = image->at(x, y);
            const float expected = (0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z) / 255.0f;
            ASSERT_NEAR(hf->at(x, y), expected, 1e-5f) << x << "," << y;
        }
    }
}

TEST_F(IoColor, FloatFormatsAreNotColourImages) {
    writeExr(path("y.exr"), 2, 2, {0, 1, 2, 3});
    auto image = loadColorImage(path("y.exr"));
    ASSERT_FALSE(image);
    EXPECT_EQ(image.error().kind, ErrorKind::Unsupported);
    EXPECT_NE(image.error().message.find("PNG or JPEG"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// OpenEXR

using IoExr = IoTest;

TEST_F(IoExr, FloatByMinMaxOrByRange) {
    writeExr(path("y.exr"), 2, 2, {2, 4, 6, 10});
    auto own = loadHeightfield(path("y.exr"));
    ASSERT_TRUE(own) << own.error().message;
    EXPECT_EQ(own->samples, (std::vector<float>{0.0f, 0.25f, 0.5f, 1.0f}));

    LoadOptions options;
    options.rangeLo = 0.0;
    options.rangeHi = 20.0;
    auto ranged = loadHeightfield(path("y.exr"), options);
    ASSERT_TRUE(ranged) << ranged.error().message;
    EXPECT_EQ(ranged->samples, (std::vector<float>{0.1f, 0.2f, 0.3f, 0.5f}));
}

TEST_F(IoExr, HalfRgbLuminanceAndChannel) {
    const std::vector<float> r = {0, 1}, g = {0, 0}, b = {0, 0.5f};
    writeExr(path("rgb.exr"), Imath::Box2i({0, 0}, {1, 0}), {{"R", r}, {"G", g}, {"B", b}},
             Imf::HALF);
    auto lum = loadHeightfield(path("rgb.exr"));
    ASSERT_TRUE(lum) << lum.error().message;
    EXPECT_EQ(lum->samples, (std::vector<float>{0.0f, 1.0f}));  // min/max of 0 and luminance

    LoadOptions options;
    options.channel = ChannelSelect::Blue;
    options.rangeLo = 0.0;
    options.rangeHi = 1.0;
    auto blue = loadHeightfield(path("rgb.exr"), options);
    ASSERT_TRUE(blue) << blue.error().message;
    EXPECT_EQ(blue->samples, (std::vector<float>{0.0f, 0.5f}));
}

TEST_F(IoExr, SingleChannelWithOffsetWindowAcrossBands) {
    // 150 rows cross the reader's 64-row bands; the window does not start at the origin.
    const Imath::Box2i window({5, -7}, {7, 142});
    std::vector<float> z(3 * 150);
    for (size_t k = 0; k < z.size(); ++k) z[k] = float(k);
    writeExr(path("z.exr"), window, {{"Z", z}});
    auto hf = loadHeightfield(path("z.exr"));
    ASSERT_TRUE(hf) << hf.error().message;
    ASSERT_EQ(hf->width, 3);
    ASSERT_EQ(hf->height, 150);
    for (size_t k = 0; k < z.size(); ++k)
        ASSERT_FLOAT_EQ(hf->samples[k], z[k] / float(z.size() - 1)) << k;
}

TEST_F(IoExr, NoUsableChannelIsUnsupported) {
    writeExr(path("za.exr"), Imath::Box2i({0, 0}, {1, 0}), {{"Z", {0, 1}}, {"Q", {1, 2}}});
    auto hf = loadHeightfield(path("za.exr"));
    ASSERT_FALSE(hf);
    EXPECT_EQ(hf.error().kind, ErrorKind::Unsupported);
    EXPECT_NE(hf.error().message.find("channels: Q, Z"), std::string::npos)
        << hf.error().message;
}

// ---------------------------------------------------------------------------------------------
// PFM and raw

using IoPfm = IoTest;

TEST_F(IoPfm, BothByteOrdersWithTopRowFirst) {
    const std::vector<float> pixels = {0, 1, 2, 3, 4, 5};  // 3×2, top row 0 1 2
    for (std::endian endian : {std::endian::little, std::endian::big}) {
        writePfm(path("g.pfm"), 3, 2, 1, pixels, endian);
        auto hf = loadHeightfield(path("g.pfm"));
        ASSERT_TRUE(hf) << hf.error().message;
        ASSERT_EQ(hf->width, 3);
        EXPECT_EQ(hf->samples, (std::vector<float>{0, 0.2f, 0.4f, 0.6f, 0.8f, 1.0f}));
    }
}

TEST_F(IoPfm, ColourLuminanceAndChannel) {
    writePfm(path("c.pfm"), 2, 1, 3, {1, 0, 0, 0, 0, 1}, std::endian::little);
    LoadOptions options;
    options.rangeLo = 0.0;
    options.rangeHi = 1.0;
    auto lum = loadHeightfield(path("c.pfm"), options);
    ASSERT_TRUE(lum) << lum.error().message;
    EXPECT_FLOAT_EQ(lum->samples[0], 0.2126f);
    EXPECT_FLOAT_EQ(lum->samples[1], 0.0722f);
    options.channel = ChannelSelect::Blue;
    auto blue = loadHeightfield(path("c.pfm"), options);
    ASSERT_TRUE(blue) << blue.error().message;
    EXPECT_EQ(blue->samples, (std::vector<float>{0, 1}));
}

using IoRaw = IoTest;

LoadOptions rawOptions(int width, int height, RawLayout::Type type) {
    LoadOptions options;
    options.raw = RawLayout{width, height, type};
    return options;
}

TEST_F(IoRaw, U8U16F32) {
    writeBytes(path("a.u8"), {0, 51, 255, 102});
    auto u8 = loadHeightfield(path("a.u8"), rawOptions(2, 2, RawLayout::Type::U8));
    ASSERT_TRUE(u8) << u8.error().message;
    EXPECT_EQ(u8->samples, (std::vector<float>{0, 0.2f, 1, 0.4f}));

    writeBytes(path("a.u16"), littleEndian<uint16_t>({0, 65535, 4660}));
    auto u16 = loadHeightfield(path("a.u16"), rawOptions(3, 1, RawLayout::Type::U16));
    ASSERT_TRUE(u16) << u16.error().message;
    EXPECT_EQ(u16->samples, (std::vector<float>{0, 1, 4660.0f / 65535.0f}));

    writeBytes(path("a.f32"), littleEndian<float>({-1, 3, 1, 0}));
    auto f32 = loadHeightfield(path("a.f32"), rawOptions(1, 4, RawLayout::Type::F32));
    ASSERT_TRUE(f32) << f32.error().message;
    EXPECT_EQ(f32->height, 4);
    EXPECT_EQ(f32->samples, (std::vector<float>{0, 1, 0.5f, 0.25f}));
}

TEST_F(IoRaw, ContentDoesNotChooseTheFormat) {
    // A PNG read with --raw is raw bytes: the option wins over the magic.
    const Bytes png = readBytes(validPng(4, 4));
    auto hf = loadHeightfield(path("valid.png"), rawOptions(int(png.size()), 1,
                                                            RawLayout::Type::U8));
    ASSERT_TRUE(hf) << hf.error().message;
    EXPECT_EQ(hf->samples[0], float(0x89) / 255.0f);
}

// ---------------------------------------------------------------------------------------------
// Non-finite samples, with where they are

using IoNonFinite = IoTest;

void expectNonFinite(const Result<Heightfield>& hf, const std::string& where) {
    ASSERT_FALSE(hf);
    EXPECT_EQ(hf.error().kind, ErrorKind::InvalidInput);
    EXPECT_NE(hf.error().message.find("non-finite"), std::string::npos) << hf.error().message;
    EXPECT_NE(hf.error().message.find(where), std::string::npos) << hf.error().message;
}

TEST_F(IoNonFinite, ExrPfmRawAreRejected) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> values = {0, 1, 2, 3, 4, nan};  // 3×2: column 2, row 1
    writeExr(path("n.exr"), 3, 2, values);
    expectNonFinite(loadHeightfield(path("n.exr")), "column 2, row 1");
    writePfm(path("n.pfm"), 3, 2, 1, values, std::endian::big);
    expectNonFinite(loadHeightfield(path("n.pfm")), "column 2, row 1");
    writeBytes(path("n.f32"), littleEndian<float>({0, inf, 2}));
    expectNonFinite(loadHeightfield(path("n.f32"), rawOptions(3, 1, RawLayout::Type::F32)),
                    "column 1, row 0");
}

// ---------------------------------------------------------------------------------------------
// Hostile inputs: each case builds its file in the test folder and names the expected error.

struct Hostile {
    const char* name;
    std::function<std::string(IoTest&)> make;  // returns the path to load
    ErrorKind kind;
    std::vector<std::string> fragments;
    LoadOptions options = {};
};

void PrintTo(const Hostile& c, std::ostream* os) { *os << c.name; }

class IoHostileTest : public IoTest, public ::testing::WithParamInterface<Hostile> {};

Bytes cut(Bytes bytes, size_t keep) {
    bytes.resize(keep);
    return bytes;
}

LoadOptions withChannel(ChannelSelect select) {
    LoadOptions options;
    options.channel = select;
    return options;
}

LoadOptions withRange(double lo, double hi) {
    LoadOptions options;
    options.rangeLo = lo;
    options.rangeHi = hi;
    return options;
}

std::string exrFile(IoTest& t) {
    std::vector<float> y(64 * 64);
    for (size_t k = 0; k < y.size(); ++k) y[k] = std::sin(float(k));
    const std::string file = t.path("valid.exr");
    writeExr(file, 64, 64, y);
    return file;
}

// An EXR file with an unknown attribute inserted first in its header, whose size field claims
// 2 GB (OpenEXR keeps unknown attributes as opaque bytes of that size).
Bytes withExrAttribute(const Bytes& exr) {
    Bytes attribute = {'n', 'o', 't', 'e', 0, 'o', 'p', 'a', 'q', 'u', 'e', 0};
    const Bytes size = littleEndian<int32_t>({0x78000000});
    attribute.insert(attribute.end(), size.begin(), size.end());
    attribute.insert(attribute.end(), {1, 2, 3, 4});
    Bytes damaged(exr.begin(), exr.begin() + 8);  // magic and version
    damaged.insert(damaged.end(), attribute.begin(), attribute.end());
    damaged.insert(damaged.end(), exr.begin() + 8, exr.end());
    return damaged;
}

const Hostile kHostile[] = {
    {"missing_file", [](IoTest& t) { return t.path("nowhere.png"); }, ErrorKind::Io,
     {"nowhere.png", "cannot open", "No such file"}},
    {"empty_file", [](IoTest& t) { return t.withBytes("empty.png", {}); },
     ErrorKind::InvalidInput, {"empty.png", "empty file"}},
    {"directory", [](IoTest& t) { return t.path(""); }, ErrorKind::Io,
     {"cannot open", "is a directory"}},
    {"garbage_bytes",
     [](IoTest& t) {
         Bytes junk;
         std::mt19937 rng(7);
         for (int k = 0; k < 4096; ++k) junk.push_back(uint8_t(rng()));
         return t.withBytes("junk.png", junk);
     },
     ErrorKind::InvalidInput, {"junk.png", "not a PNG/JPEG/EXR/PFM file", "--raw"}},
    {"truncated_png",
     [](IoTest& t) {
         const Bytes png = readBytes(t.validPng());
         return t.withBytes("half.png", cut(png, png.size() / 2));
     },
     ErrorKind::InvalidInput, {"half.png", "truncated PNG"}},
    {"png_signature_and_header_only",
     [](IoTest& t) { return t.withBytes("head.png", cut(readBytes(t.validPng()), 33)); },
     ErrorKind::InvalidInput, {"truncated PNG"}},
    {"png_idat_byte_flipped",
     [](IoTest& t) {
         Bytes png = readBytes(t.validPng());
         png[find(png, "IDAT") + 20] ^= 0x55;
         return t.withBytes("flip.png", png);
     },
     ErrorKind::InvalidInput, {"flip.png", "corrupt PNG", "IDAT"}},
    {"png_idat_crc_mismatch",
     [](IoTest& t) {
         Bytes png = readBytes(t.validPng());
         png[find(png, "IEND") - 8] ^= 0x55;  // last byte of the IDAT CRC
         return t.withBytes("crc.png", png);
     },
     ErrorKind::InvalidInput, {"crc.png", "corrupt PNG", "CRC error"}},
    {"png_idat_bad_deflate_valid_crc",
     [](IoTest& t) {
         Bytes png = readBytes(t.validPng());
         const size_t type = find(png, "IDAT");
         const uint32_t length = uint32_t(png[type - 4]) << 24 | png[type - 3] << 16 |
                                 png[type - 2] << 8 | png[type - 1];
         for (size_t k = type + 6; k < type + 4 + length; ++k) png[k] = 0xff;
         const uLong crc = crc32(0, png.data() + type, uInt(length + 4));
         for (int b = 0; b < 4; ++b) png[type + 4 + length + b] = uint8_t(crc >> (24 - 8 * b));
         return t.withBytes("zlib.png", png);
     },
     ErrorKind::InvalidInput, {"zlib.png", "corrupt PNG"}},
    {"png_claims_100000_square",
     [](IoTest& t) { return t.withBytes("huge.png", pngClaiming(100000, 100000)); },
     ErrorKind::InvalidInput, {"huge.png", "100000x100000", "limit of 65536 per side"}},
    {"png_claims_too_many_samples",
     [](IoTest& t) { return t.withBytes("many.png", pngClaiming(60000, 60000)); },
     ErrorKind::InvalidInput, {"many.png", "limit of 268435456", "--max-samples"}},
    {"png_alpha_of_grey", [](IoTest& t) { return t.validPng(); }, ErrorKind::BadArgument,
     {"--channel a", "no alpha channel"}, withChannel(ChannelSelect::Alpha)},
    {"png_height_range", [](IoTest& t) { return t.validPng(); }, ErrorKind::BadArgument,
     {"--height-range", "integer codes"}, withRange(0, 10)},
    {"truncated_jpeg",
     [](IoTest& t) {
         const Bytes jpeg = readBytes(sourceFile("data/finland-map-600.jpg"));
         return t.withBytes("half.jpg", cut(jpeg, jpeg.size() / 2));
     },
     ErrorKind::InvalidInput, {"half.jpg", "truncated JPEG"}},
    {"jpeg_garbage_after_soi",
     [](IoTest& t) { return t.withBytes("bad.jpg", {0xff, 0xd8, 0xff, 0xe0, 0, 2, 1, 2}); },
     ErrorKind::InvalidInput, {"bad.jpg", "corrupt JPEG"}},
    {"jpeg_12_bit",
     [](IoTest& t) {
         Bytes jpeg = readBytes(sourceFile("data/finland-map-600.jpg"));
         jpeg[find(jpeg, std::string_view("\xff\xc0", 2)) + 4] = 12;  // frame precision
         return t.withBytes("deep.jpg", jpeg);
     },
     ErrorKind::Unsupported, {"deep.jpg", "12-bit JPEG not supported"}},
    {"jpeg_arithmetic_coded",
     [](IoTest& t) {
         Bytes jpeg = readBytes(sourceFile("data/finland-map-600.jpg"));
         jpeg[find(jpeg, std::string_view("\xff\xc0", 2)) + 1] = 0xc9;
         return t.withBytes("arith.jpg", jpeg);
     },
     ErrorKind::Unsupported, {"arith.jpg", "JPEG variant not supported", "0xc9"}},
    {"truncated_exr",
     [](IoTest& t) {
         const Bytes exr = readBytes(exrFile(t));
         return t.withBytes("half.exr", cut(exr, exr.size() / 2));
     },
     ErrorKind::InvalidInput, {"half.exr", "EXR"}},
    {"exr_header_only",
     [](IoTest& t) {
         const Bytes exr = readBytes(exrFile(t));
         return t.withBytes("head.exr", cut(exr, find(exr, "screenWindowWidth") + 30));
     },
     ErrorKind::InvalidInput, {"head.exr", "EXR"}},
    {"exr_claims_100000_wide",
     [](IoTest& t) {
         Bytes exr = readBytes(exrFile(t));
         const size_t maxX = find(exr, "dataWindow") + std::strlen("dataWindow") + 1 + 6 + 4 + 8;
         const Bytes wide = littleEndian<int32_t>({99999});
         std::copy(wide.begin(), wide.end(), exr.begin() + std::ptrdiff_t(maxX));
         return t.withBytes("wide.exr", exr);
     },
     ErrorKind::InvalidInput, {"wide.exr", "65536"}},
    // Found by fuzz_jpeg (UBSan): a Huffman table whose code counts add up to more than 256
    // made stb_image write past its table. Refused by the marker walk.
    {"jpeg_huffman_counts_over_256",
     [](IoTest& t) {
         Bytes jpeg = readBytes(sourceFile("data/finland-map-600.jpg"));
         const size_t dht = find(jpeg, "\xff\xc4");
         std::fill(jpeg.begin() + std::ptrdiff_t(dht + 5), jpeg.begin() + std::ptrdiff_t(dht + 21),
                   uint8_t(17));  // 16 counts of 17: 272 symbols
         return t.withBytes("huffman.jpg", jpeg);
     },
     ErrorKind::InvalidInput, {"huffman.jpg", "corrupt JPEG: bad Huffman table"}},
    // Found by a longer fuzz_jpeg run (UBSan): a progressive AC scan naming an AC table no DHT
    // defined made stb_image read an uninitialized table and index far out of bounds.
    {"jpeg_scan_with_undefined_huffman_table",
     [](IoTest& t) {
         return t.withBytes("scan.jpg", readBytes(sourceFile("fuzz/corpus/jpeg/regression-undefined-ac-table.jpg")));
     },
     ErrorKind::InvalidInput, {"scan.jpg", "uses a Huffman table that is not defined"}},
    // Found by a longer fuzz_jpeg run (UBSan in stb_image: a shift by 32 on corrupt entropy
    // data); JPEG now goes through libjpeg-turbo, whose corrupt-data warnings are errors.
    {"jpeg_corrupt_entropy_data",
     [](IoTest& t) {
         return t.withBytes("entropy.jpg", readBytes(sourceFile("fuzz/corpus/jpeg/regression-corrupt-entropy-data.jpg")));
     },
     ErrorKind::InvalidInput, {"entropy.jpg", "corrupt or unsupported JPEG: Corrupt JPEG data"}},
    // Found by longer fuzz_exr / fuzz_map_file runs (UBSan): a preview attribute of
    // 2^31 × 2^31 pixels overflowed the header walk's size check.
    {"exr_preview_size_overflow",
     [](IoTest& t) {
         return t.withBytes("preview.exr", readBytes(sourceFile("fuzz/corpus/exr/regression-preview-size-overflow.exr")));
     },
     ErrorKind::InvalidInput, {"preview.exr", "(preview) claims more bytes"}},
    // Found by fuzz_map_file: OpenEXR 3.1 allocates an attribute's declared size before reading
    // it, so these 300 bytes cost 2 GB. Refused before OpenEXR sees the header.
    {"exr_attribute_claims_2gb",
     [](IoTest& t) { return t.withBytes("claims.exr", withExrAttribute(readBytes(exrFile(t)))); },
     ErrorKind::InvalidInput, {"claims.exr", "attribute 'note' (opaque) claims more bytes"}},
    {"pfm_bad_header",
     [](IoTest& t) { return t.withBytes("bad.pfm", {'P', 'f', '\n', 'x', 'y', '\n'}); },
     ErrorKind::InvalidInput, {"bad.pfm", "bad PFM header"}},
    {"pfm_zero_scale",
     [](IoTest& t) {
         const std::string text = "Pf\n1 1\n0.0\n\1\2\3\4";
         return t.withBytes("zero.pfm", Bytes(text.begin(), text.end()));
     },
     ErrorKind::InvalidInput, {"zero.pfm", "bad PFM header", "non-zero scale"}},
    {"pfm_too_little_data",
     [](IoTest& t) {
         const std::string text = "PF\n4 4\n-1.0\n";
         Bytes bytes(text.begin(), text.end());
         bytes.resize(bytes.size() + 100);
         return t.withBytes("short.pfm", bytes);
     },
     ErrorKind::InvalidInput, {"short.pfm", "truncated PFM", "needs 192 bytes", "has 100"}},
    {"pfm_claims_huge",
     [](IoTest& t) {
         const std::string text = "Pf\n9999999999 3\n-1.0\nxxxx";
         return t.withBytes("huge.pfm", Bytes(text.begin(), text.end()));
     },
     ErrorKind::InvalidInput, {"huge.pfm", "limit of 65536 per side"}},
    {"raw_wrong_size",
     [](IoTest& t) { return t.withBytes("short.u16", Bytes(49, 0)); },
     ErrorKind::InvalidInput, {"short.u16", "raw 5x5:u16", "needs exactly 50 bytes", "has 49"},
     rawOptions(5, 5, RawLayout::Type::U16)},
    {"raw_too_large",
     [](IoTest& t) { return t.withBytes("big.u8", Bytes(17, 0)); },
     ErrorKind::InvalidInput, {"big.u8", "needs exactly 16 bytes", "has 17"},
     rawOptions(4, 4, RawLayout::Type::U8)},
};

TEST_P(IoHostileTest, IsAnErrorThatSaysWhy) {
    const Hostile& c = GetParam();
    const std::string file = c.make(*this);
    auto hf = loadHeightfield(file, c.options);
    ASSERT_FALSE(hf) << c.name << " loaded";
    RecordProperty("message", hf.error().message);  // the table of messages, in --gtest_output
    EXPECT_EQ(int(hf.error().kind), int(c.kind)) << hf.error().message;
    for (const std::string& fragment : c.fragments)
        EXPECT_NE(hf.error().message.find(fragment), std::string::npos)
            << "missing '" << fragment << "' in: " << hf.error().message;
}

// The in-memory entry point (what the fuzz targets use) reads the same bytes the same way.
TEST_P(IoHostileTest, FromMemoryIsTheSameError) {
    const Hostile& c = GetParam();
    const std::string file = c.make(*this);
    if (!fs::is_regular_file(file)) GTEST_SKIP() << "no bytes to read: " << c.name;
    auto fromFile = loadHeightfield(file, c.options);
    auto fromMemory = decodeHeightfield(readBytes(file), file, c.options);
    ASSERT_FALSE(fromMemory) << c.name << " loaded";
    EXPECT_EQ(int(fromMemory.error().kind), int(fromFile.error().kind));
    EXPECT_EQ(fromMemory.error().message, fromFile.error().message);
}

INSTANTIATE_TEST_SUITE_P(IoHostile, IoHostileTest, ::testing::ValuesIn(kHostile),
                         [](const auto& info) { return std::string(info.param.name); });

TEST_F(IoColor, HostileColourFilesAreErrors) {
    const Bytes png = readBytes(validPng());
    auto truncated = loadColorImage(withBytes("half.png", cut(png, png.size() / 2)));
    ASSERT_FALSE(truncated);
    EXPECT_EQ(truncated.error().kind, ErrorKind::InvalidInput);
    EXPECT_NE(truncated.error().message.find("truncated PNG"), std::string::npos);
    const Bytes jpeg = readBytes(sourceFile("data/finland-map-600.jpg"));
    auto cutJpeg = loadColorImage(withBytes("half.jpg", cut(jpeg, jpeg.size() / 3)));
    ASSERT_FALSE(cutJpeg);
    EXPECT_NE(cutJpeg.error().message.find("truncated JPEG"), std::string::npos);
    auto huge = loadColorImage(withBytes("huge.png", pngClaiming(100000, 100000)));
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.error().message.find("limit of 65536"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Found by fuzz_png: libpng allocates and clears an ancillary chunk's declared length before
// reading it, so a 105-byte PNG whose tEXt length read 0x29000013 took 680 MB and 8 s before it
// was refused as truncated. The chunk lengths are now checked against the file first.

// Peak resident memory, in MB (capped at 250), of a child process that loads `file`.
int peakMegabytesLoading(const std::string& file) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        (void)loadHeightfield(file);
        rusage usage{};
        ::getrusage(RUSAGE_SELF, &usage);
        ::_exit(int(std::min<long>(usage.ru_maxrss / 1024, 250)));
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST_F(IoTest, ChunkLongerThanTheFileIsRefusedBeforeAllocating) {
    const Bytes valid = readBytes(validPng());
    Bytes damaged(valid.begin(), valid.begin() + 33);  // signature and IHDR
    appendChunk(damaged, "tEXt", {'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'x'});
    damaged.insert(damaged.end(), valid.begin() + 33, valid.end());
    damaged[33] = 0x29;  // the tEXt length: 9 → 0x29000009
    const std::string file = withBytes("claims.png", damaged);
    auto hf = loadHeightfield(file);
    ASSERT_FALSE(hf);
    EXPECT_NE(hf.error().message.find("truncated PNG"), std::string::npos) << hf.error().message;
    const int baseline = peakMegabytesLoading(path("valid.png"));
    const int peak = peakMegabytesLoading(file);
    ASSERT_GT(baseline, 0);
    EXPECT_LT(peak, baseline + 64) << "MB; loading the valid file took " << baseline;
}

// ---------------------------------------------------------------------------------------------
// From memory: every format decodes to the same heightfield or colour image as from its file.

TEST_F(IoTest, FromMemoryMatchesFromFile) {
    std::vector<float> y(6 * 5);
    for (size_t k = 0; k < y.size(); ++k) y[k] = std::cos(float(k));
    writeExr(path("m.exr"), 6, 5, y);
    std::string pfm = "Pf\n2 2\n-1\n";
    for (float v : {0.5f, -2.0f, 4.0f, 1.0f}) pfm.append(reinterpret_cast<const char*>(&v), 4);
    const std::string files[] = {validPng(), sourceFile("data/finland-map-600.jpg"), path("m.exr"),
                                 withBytes("m.pfm", Bytes(pfm.begin(), pfm.end()))};
    for (const std::string& file : files) {
        SCOPED_TRACE(file);
        auto fromFile = loadHeightfield(file);
        auto fromMemory = decodeHeightfield(readBytes(file), file);
        ASSERT_TRUE(fromFile) << fromFile.error().message;
        ASSERT_TRUE(fromMemory) << fromMemory.error().message;
        EXPECT_EQ(fromMemory->width, fromFile->width);
        EXPECT_EQ(fromMemory->height, fromFile->height);
        EXPECT_EQ(fromMemory->samples, fromFile->samples);
    }
    const std::string jpeg = sourceFile("data/finland-map-600.jpg");
    auto colorFile = loadColorImage(jpeg);
    auto colorMemory = decodeColorImage(readBytes(jpeg), jpeg);
    ASSERT_TRUE(colorFile && colorMemory);
    EXPECT_EQ(colorMemory->width, colorFile->width);
    EXPECT_TRUE(colorMemory->pixels == colorFile->pixels);
    LoadOptions raw;
    raw.raw = RawLayout{2, 2, RawLayout::Type::U8};
    auto rawHf = decodeHeightfield(Bytes{0, 51, 102, 255}, "mem.u8", raw);
    ASSERT_TRUE(rawHf) << rawHf.error().message;
    EXPECT_EQ(rawHf->samples, (std::vector<float>{0.0f, 0.2f, 0.4f, 1.0f}));
    auto empty = decodeHeightfield(Bytes{}, "mem.png");
    ASSERT_FALSE(empty);
    EXPECT_EQ(empty.error().message, "mem.png: empty file");
}

// ---------------------------------------------------------------------------------------------
// The CLI maps a corrupt heightfield to exit code 3 with the documented prefix.

TEST_F(IoTest, CliReportsCorruptFileAsInvalidInput) {
    const Bytes png = readBytes(validPng());
    const std::string corrupt = withBytes("half.png", cut(png, png.size() / 2));
    writeBytes(path("rays.csv"), {'0', ',', '0', ',', '1', ',', '0', ',', '0', ',', '-', '1'});
    const std::string command = fmt::format("'{}' trace '{}' --rays '{}' -o - 2>'{}'",
                                            RELIEF_CLI_PATH, corrupt, path("rays.csv"),
                                            path("stderr.txt"));
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3);
    const Bytes err = readBytes(path("stderr.txt"));
    const std::string text(err.begin(), err.end());
    EXPECT_EQ(text.rfind("relief: error: ", 0), 0u) << text;
    EXPECT_NE(text.find("truncated PNG"), std::string::npos) << text;
}

}  // namespace
}  // namespace relief
