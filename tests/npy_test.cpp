// The hand-written .npy reader and writer (io/npy.h), the ray and hit files built on them
// (io/ray_io.h: .npy and CSV with tmax and fetches), and the float image writers (PFM, .npy)
// read back through relief's own PFM reader.
#include <gtest/gtest.h>
#include <relief/io/image_write.h>
#include <relief/io/npy.h>
#include <relief/io/ray_io.h>
#include <relief/io/read_common.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace relief {
namespace {

namespace fs = std::filesystem;

using Bytes = std::vector<unsigned char>;

Bytes bytesOf(const std::string& s) { return Bytes(s.begin(), s.end()); }

// A file as NumPy writes it (version 1.0 or, with a 4-byte header length, 2.0 or later), with
// the dict given verbatim and `data` after it.
std::string npyWithDict(const std::string& dict, const std::string& data, char major = 1) {
    const size_t lengthBytes = major == 1 ? 2 : 4;
    std::string header = dict;
    header.append((64 - (8 + lengthBytes + header.size() + 1) % 64) % 64, ' ');
    header.push_back('\n');
    std::string out = "\x93NUMPY";
    out += major;
    out += '\0';
    for (size_t k = 0; k < lengthBytes; ++k) out += char((header.size() >> (8 * k)) & 0xff);
    return out + header + data;
}

template <class T>
std::string floats(std::initializer_list<T> values) {
    std::string out;
    for (T v : values) out.append(reinterpret_cast<const char*>(&v), sizeof v);
    return out;
}

std::string raysDict(const std::string& descr, const std::string& shape) {
    return "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
}

Result<std::vector<Ray>> decode(const std::string& file, size_t maxRays = kDefaultMaxRays) {
    return decodeNpyRays(bytesOf(file), "r.npy", maxRays);
}

void expectError(const Result<std::vector<Ray>>& r, ErrorKind kind, const std::string& fragment) {
    ASSERT_FALSE(r) << "accepted; expected: " << fragment;
    EXPECT_EQ(r.error().kind, kind) << r.error().message;
    EXPECT_NE(r.error().message.find(fragment), std::string::npos) << r.error().message;
}

TEST(Npy, PreambleIsWhatNumPyWrites) {
    const NpyField f4[] = {{"", "<f4"}};
    const int64_t shape[] = {3, 6};
    const std::string p = npyPreamble(f4, shape);
    EXPECT_EQ(p.size() % 64, 0u);
    EXPECT_EQ(p.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    EXPECT_NE(p.find("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 6), }"),
              std::string::npos);
    EXPECT_EQ(p.back(), '\n');
    const int64_t one[] = {5};
    EXPECT_NE(npyPreamble(kHitFields, one).find("'shape': (5,)"), std::string::npos);
    EXPECT_NE(npyPreamble(kHitFields, one).find("[('hit', '|b1'), ('t', '<f4')"),
              std::string::npos);
}

TEST(Npy, RaysRoundTripExactlyWithAndWithoutTmax) {
    std::vector<Ray> rays = {Ray{vec3(1.5f, 2.25f, 30.0f), glm::normalize(vec3(0.1f, 0.2f, -1.0f))},
                             Ray{vec3(-5.0f, 5.0f, 1.0f), vec3(1.0f, 0.0f, 0.0f)}};
    for (bool tmax : {false, true}) {
        if (tmax) rays[1].tMax = 12.5f;
        for (const auto& [text, name] :
             {std::pair{npyRays(rays), "npy"}, std::pair{formatRays(rays), "csv"}}) {
            auto back = std::string(name) == "npy" ? decode(text) : parseRays(text, "r.csv");
            ASSERT_TRUE(back) << back.error().message;
            ASSERT_EQ(back->size(), rays.size());
            for (size_t k = 0; k < rays.size(); ++k) {
                EXPECT_EQ((*back)[k].origin, rays[k].origin) << name;
                EXPECT_EQ((*back)[k].direction, rays[k].direction) << name;
                EXPECT_EQ((*back)[k].tMax, rays[k].tMax) << name;
            }
        }
    }
    EXPECT_EQ(formatRays(rays).substr(0, 23), "ox,oy,oz,dx,dy,dz,tmax\n");
}

TEST(Npy, Float64RaysWithTmaxAreNormalized) {
    const std::string file =
        npyWithDict(raysDict("<f8", "(2, 7)"), floats<double>({1, 2, 3, 0, 0, -2, 5,  //
                                                               4, 5, 6, 3, 0, 4, INFINITY}));
    auto rays = decode(file);
    ASSERT_TRUE(rays) << rays.error().message;
    ASSERT_EQ(rays->size(), 2u);
    EXPECT_EQ((*rays)[0].direction, vec3(0, 0, -1));
    EXPECT_EQ((*rays)[0].tMax, 5.0f);
    EXPECT_FLOAT_EQ((*rays)[1].direction.x, 0.6f);
    EXPECT_EQ((*rays)[1].tMax, kInfinity);
    // Version 2.0 (a 4-byte header length) and the native byte order '=' read the same.
    auto again = decode(npyWithDict(raysDict("=f8", "(2, 7)"), file.substr(file.size() - 112), 2));
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_EQ((*again)[1].tMax, kInfinity);
}

TEST(Npy, MalformedFilesAreRefusedWithTheReason) {
    const std::string six = floats<float>({1, 2, 3, 0, 0, -1});
    expectError(decode("not numpy at all"), ErrorKind::InvalidInput, "no \\x93NUMPY magic");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 6)"), six, 3)), ErrorKind::Unsupported,
                "version 3.0");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 6)"), six).substr(0, 9)),
                ErrorKind::InvalidInput, "truncated before its length");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 6)"), six).substr(0, 40)),
                ErrorKind::InvalidInput, "bad .npy header: truncated");
    expectError(
        decode(npyWithDict("{'descr': '<f4', 'fortran_order': True, 'shape': (1, 6)}", six)),
        ErrorKind::Unsupported, "fortran_order=True");
    expectError(decode(npyWithDict(raysDict(">f4", "(1, 6)"), six)), ErrorKind::Unsupported,
                "big-endian dtype '>f4'");
    expectError(decode(npyWithDict(raysDict("<c8", "(1, 6)"), six)), ErrorKind::Unsupported,
                "dtype '<c8' is not one relief reads");
    expectError(decode(npyWithDict(raysDict("<i4", "(1, 6)"), six)), ErrorKind::InvalidInput,
                "float32 or float64 of shape (N, 6)");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 5)"), six.substr(0, 20))),
                ErrorKind::InvalidInput, "this is <f4 (1, 5)");
    expectError(decode(npyWithDict(raysDict("<f4", "(6,)"), six)), ErrorKind::InvalidInput,
                "this is <f4 (6,)");
    expectError(decode(npyWithDict(raysDict("<f4", "(2, 6)"), six)), ErrorKind::InvalidInput,
                "truncated .npy: shape (2, 6) needs 48 bytes of data, the file has 24");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 6)"), six + "xx")), ErrorKind::InvalidInput,
                "2 bytes after the data");
    // Absurd sizes are refused from the header, before anything is allocated.
    expectError(decode(npyWithDict(raysDict("<f4", "(99999999999999999, 6)"), six)),
                ErrorKind::InvalidInput, "absurd shape");
    expectError(decode(npyWithDict(raysDict("<f4", "(999999999999999999999, 6)"), six)),
                ErrorKind::InvalidInput, "not a Python dict literal");
    expectError(decode(npyWithDict(raysDict("<f4", "(1000000, 6)"), six)), ErrorKind::InvalidInput,
                "truncated .npy");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 6)"), six), 0), ErrorKind::InvalidInput,
                "1 rays, more than 0 (--max-rays)");
    // The dict itself.
    expectError(decode(npyWithDict("[1, 2]", six)), ErrorKind::InvalidInput, "not a Python dict");
    expectError(decode(npyWithDict("{'descr': '<f4', 'shape': (1, 6)}", six)),
                ErrorKind::InvalidInput, "needs the keys");
    expectError(decode(npyWithDict("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 6), "
                                   "'extra': 1}",
                                   six)),
                ErrorKind::InvalidInput, "unexpected or repeated key 'extra'");
    expectError(decode(npyWithDict(std::string(20000, '{'), six)), ErrorKind::InvalidInput,
                "bytes long (at most 10000)");
    expectError(decode(npyWithDict(std::string(200, '(') + std::string(200, ')'), six)),
                ErrorKind::InvalidInput, "not a Python dict");
    expectError(decode(npyWithDict("{'descr': [('a', '<f4', (6,))], 'fortran_order': False, "
                                   "'shape': (1,)}",
                                   six)),
                ErrorKind::Unsupported, "('name', 'type') pairs");
    // A bad value names its row, as a CSV line names its line.
    expectError(
        decode(npyWithDict(raysDict("<f4", "(2, 6)"), six + floats<float>({1, 2, 3, 0, 0, 0}))),
        ErrorKind::InvalidInput, "r.npy: row 1: zero or unusable direction");
    expectError(decode(npyWithDict(raysDict("<f4", "(1, 7)"), six + floats<float>({-1}))),
                ErrorKind::InvalidInput, "r.npy: row 0: tmax -1 is not a number >= 0");
}

TEST(RayCsv, TmaxColumnIsOptionalPerLine) {
    auto rays = parseRays(
        "ox,oy,oz,dx,dy,dz,tmax\n1,2,3,0,0,-1,4.5\n1,2,3,0,0,-1\n1,2,3,0,0,-1,inf\n", "r.csv");
    ASSERT_TRUE(rays) << rays.error().message;
    ASSERT_EQ(rays->size(), 3u);
    EXPECT_EQ((*rays)[0].tMax, 4.5f);
    EXPECT_EQ((*rays)[1].tMax, kInfinity);
    EXPECT_EQ((*rays)[2].tMax, kInfinity);
    for (const char* bad : {"1,2,3,0,0,-1,-2\n", "1,2,3,0,0,-1,nan\n"}) {
        auto r = parseRays(bad, "r.csv");
        ASSERT_FALSE(r) << bad;
        EXPECT_NE(r.error().message.find("r.csv:1: tmax"), std::string::npos) << r.error().message;
    }
    auto eight = parseRays("1,2,3,0,0,-1,4,5\n", "r.csv");
    ASSERT_FALSE(eight);
    EXPECT_NE(eight.error().message.find("expected six numbers"), std::string::npos);
}

TEST(HitFiles, CsvAndNpyCarryFetches) {
    std::vector<Hit> hits(2);
    hits[0] = Hit{true, 2.5f, vec3(1, 2, 3), 7, 11};
    hits[1].steps = 4;
    hits[1].fetches = 9;
    EXPECT_EQ(formatHits(hits),
              "hit,t,x,y,z,steps,fetches\n1,2.5,1,2,3,7,11\n0,inf,nan,nan,nan,4,9\n");
    const std::string npy = npyHits(hits);
    FilePtr in(::fmemopen(const_cast<char*>(npy.data()), npy.size(), "r"));
    auto header = readNpyHeader(in.get(), int64_t(npy.size()), "h.npy");
    ASSERT_TRUE(header) << header.error().message;
    EXPECT_EQ(header->itemBytes, 25);
    EXPECT_EQ(header->shape, (std::vector<int64_t>{2}));
    ASSERT_EQ(header->fields.size(), std::size(kHitFields));
    const char* row = npy.data() + header->dataOffset;
    float t, y;
    int32_t steps, fetches;
    std::memcpy(&t, row + 1, 4);
    std::memcpy(&y, row + 9, 4);
    std::memcpy(&steps, row + 17, 4);
    std::memcpy(&fetches, row + 21, 4);
    EXPECT_EQ(row[0], 1);
    EXPECT_EQ(t, 2.5f);
    EXPECT_EQ(y, 2.0f);
    EXPECT_EQ(steps, 7);
    EXPECT_EQ(fetches, 11);
    std::memcpy(&t, row + 25 + 1, 4);
    std::memcpy(&fetches, row + 25 + 21, 4);
    EXPECT_EQ(row[25], 0);
    EXPECT_EQ(t, kInfinity);
    EXPECT_EQ(fetches, 9);
}

class FloatImages : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("relief_npy_test_" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
        // 3×2, row 0 at the top; a miss is +inf.
        m_image = ImageF(3, 2);
        m_image.pixels = {0.5f, 1.0f, kInfinity, 3.0f, 4.25f, 5.0f};
    }
    void TearDown() override { fs::remove_all(m_dir); }

    std::string write(const std::string& name) {
        const std::string path = (m_dir / name).string();
        OutputSet outputs;
        EXPECT_TRUE(writeFloatImage(outputs, path, m_image));
        EXPECT_TRUE(outputs.commit());
        std::ifstream in(path, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }

    fs::path m_dir;
    ImageF m_image;
};

TEST_F(FloatImages, PfmRoundTripsThroughThePfmReader) {
    const std::string bytes = write("d.PFM");
    ASSERT_EQ(bytes.substr(0, 12), "Pf\n3 2\n-1.0\n");
    float first;
    std::memcpy(&first, bytes.data() + 12, 4);
    EXPECT_EQ(first, 3.0f);  // the bottom row comes first, as the format has it
    auto file = FileReader::open((m_dir / "d.PFM").string());
    ASSERT_TRUE(file) << file.error().message;
    ASSERT_EQ(detectFormat(file->head()), FileFormat::Pfm);
    auto decoder = makePfmHeightDecoder(*file, ChannelSelect::Luminance);
    auto decoded = decodeImage(*decoder, file->path(), kDefaultMaxSamples);
    ASSERT_TRUE(decoded) << decoded.error().message;
    EXPECT_EQ(decoded->image.width, 3);
    EXPECT_EQ(decoded->image.pixels, m_image.pixels);
}

TEST_F(FloatImages, NpyIsHeightByWidthTopRowFirst) {
    const std::string bytes = write("d.npy");
    FilePtr in(::fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "r"));
    auto header = readNpyHeader(in.get(), int64_t(bytes.size()), "d.npy");
    ASSERT_TRUE(header) << header.error().message;
    EXPECT_TRUE(header->plain("<f4"));
    EXPECT_EQ(header->shape, (std::vector<int64_t>{2, 3}));
    std::vector<float> values(6);
    std::memcpy(values.data(), bytes.data() + header->dataOffset, 24);
    EXPECT_EQ(values, m_image.pixels);
    EXPECT_EQ(write("d.exr").substr(0, 4), "\x76\x2f\x31\x01");  // any other name: OpenEXR
}

}  // namespace
}  // namespace relief
