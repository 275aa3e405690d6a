// Issue 22 classes 4, 6, 8 and 9: inputs that block or swallow memory, numbers that mean nothing,
// reading and geometry edge cases, statistics over the pixels that matter. A hostile-input table
// run through the CLI, then unit tests of the mechanisms (the typed open, the ray reader, the PFM
// header, Surface::nearBox, compareHits' covered pixels).
#include <gtest/gtest.h>
#include <relief/core/heightfield.h>
#include <relief/io/heightfield_io.h>
#include <relief/io/ray_io.h>
#include <relief/io/read_common.h>
#include <relief/render/compare.h>
#include <relief/surface/surface.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace relief {
namespace {

namespace fs = std::filesystem;

struct InputCase {
    const char* name;
    std::string args;  // after "relief"; {tmp} is the test's folder
    int exitCode;
    const char* fragment;  // expected in stdout or stderr
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

// A 4×3 grey PFM (little endian) with the header lines given.
std::string pfm(const std::string& header) {
    std::string data;
    for (int k = 0; k < 12; ++k) {
        const float v = 0.1f * float(k % 7);
        data.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    return header + data;
}

class Inputs : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        tmp = fs::temp_directory_path() / ("relief_inputs_test_" + std::to_string(::getpid()));
        fs::create_directories(tmp / "dir");
        ASSERT_EQ(::mkfifo((tmp / "fifo").c_str(), 0600), 0) << std::strerror(errno);
        writeBytes(tmp / "nul.csv", std::string("1,1,5,0,0,-1\n2,2,5,0,0,-1\0,junk\n", 31));
        writeBytes(tmp / "rays.csv", "8,8,30,0,0,-1\n9,9,30,0,0,-1\n10,10,30,0,0,-1\n");
        writeBytes(tmp / "far20.csv", "1e20,1e20,1e20,-1,-1,-1\n");
        // The same ray from far away and from near the box: the far one must hit where the near one
        // does.
        writeBytes(tmp / "far12.csv", "1e12,1e12,1e12,-1,-1,-1\n100,100,100,-1,-1,-1\n");
        writeBytes(tmp / "lf.pfm", pfm("Pf\n4 3\n-1.0\n"));
        writeBytes(tmp / "crlf.pfm", pfm("Pf\r\n4 3\r\n-1.0\r\n"));
        writeBytes(tmp / "comment.pfm", pfm("Pf\n# written by hand\n4 3\n-1.0\n"));
    }
    static void TearDownTestSuite() { fs::remove_all(tmp); }

    struct Output {
        int code = -1;
        std::string out, err;
    };
    // `timeout` so that a regression to a blocking open fails instead of hanging the suite.
    static Output relief(std::string args) {
        for (size_t p; (p = args.find("{tmp}")) != std::string::npos;)
            args.replace(p, 5, tmp.string());
        const fs::path out = tmp / "out.txt", err = tmp / "err.txt";
        const std::string command = "timeout 60 " + std::string(RELIEF_CLI_PATH) + " " + args +
                                    " >" + out.string() + " 2>" + err.string() + " </dev/zero";
        const int status = std::system(command.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
    }
    static inline fs::path tmp;
};

const std::string kMap = "gen:fbm:32x32";
const std::string kRender = "render " + kMap + " --size 16x16 -o {tmp}/o.png ";

const InputCase kInputCases[] = {
    // Class 4: FIFOs, directories and devices as inputs are refused before a byte is read.
    {"heightfield FIFO", "info {tmp}/fifo", 2, "is a FIFO (pipe), not an image file"},
    {"heightfield dir", "info {tmp}/dir", 2, "is a directory"},
    {"heightfield device", "info /dev/zero", 2, "is a character device"},
    {"--color FIFO", kRender + "--color {tmp}/fifo", 2, "fifo: cannot open: is a FIFO"},
    {"--normal FIFO", kRender + "--normal {tmp}/fifo", 2, "fifo: cannot open: is a FIFO"},
    {"--maps FIFO", "trace " + kMap + " -t cone --maps {tmp}/fifo --rays {tmp}/rays.csv", 2,
     "fifo: cannot open: is a FIFO"},
    {"--rays FIFO", "trace " + kMap + " --rays {tmp}/fifo", 2, "is a FIFO (pipe), not a ray file"},
    {"--rays dir", "trace " + kMap + " --rays {tmp}/dir", 2, "is a directory, not a ray file"},
    {"--rays device", "trace " + kMap + " --rays /dev/zero", 2, "is a character device"},
    {"--rays - (stdin of NULs)", "trace " + kMap + " --rays -", 3, "stdin:1: NUL byte"},
    {"--rays NUL", "trace " + kMap + " --rays {tmp}/nul.csv", 3, "nul.csv:2: NUL byte"},
    {"--max-rays", "trace " + kMap + " --rays {tmp}/rays.csv --max-rays 2", 3,
     "rays.csv:3: more than 2 rays (--max-rays)"},
    {"--max-rays enough", "trace " + kMap + " --rays {tmp}/rays.csv --max-rays 3", 0, "hit,t"},
    {"--max-rays 0", "trace " + kMap + " --rays {tmp}/rays.csv --max-rays 0", 1, "--max-rays"},
    // Class 6: numbers that mean nothing, with the range in the message.
    {"--elevation nan", kRender + "--elevation nan", 1,
     "--elevation: 'nan' is not a finite number from -90 to 90"},
    {"--fov nan", kRender + "--fov nan", 1, "from 1 to 170"},
    {"--fov inf", kRender + "--fov inf", 1, "'inf' is not a finite number"},
    {"--distance nan", kRender + "--distance nan", 1, "--distance: 'nan'"},
    {"--azimuth inf", kRender + "--azimuth inf", 1, "from -360 to 360"},
    {"--azimuth -nan", kRender + "--azimuth -nan", 1, "--azimuth"},
    {"--light-elevation nan", kRender + "--light-elevation nan", 1, "--light-elevation"},
    {"--light-azimuth inf", kRender + "--light-azimuth inf", 1, "--light-azimuth"},
    {"--depth nan", kRender + "--depth nan", 1, "--depth: 'nan'"},
    {"--depth-ratio inf", kRender + "--depth-ratio inf", 1, "--depth-ratio"},
    {"--phi-max nan", kRender + "-t safety-cc --phi-max nan", 1, "'phi-max' = nan is out of range"},
    {"--size overflow", "render " + kMap + " --size 4294967328x24 -o {tmp}/o.png", 1,
     "--size '4294967328x24'"},
    {"--size trailing", "render " + kMap + " --size 16x16x -o {tmp}/o.png", 1, "expected WxH"},
    {"--radius nan", kRender + "--surface sphere --radius nan", 1, "--radius: 'nan'"},
    {"--max-samples negative", "info " + kMap + " --max-samples -5", 1, "--max-samples"},
    {"--max-samples overflow", "info " + kMap + " --max-samples 99999999999999999999", 1,
     "--max-samples"},
    {"--threads huge", kRender + "--threads 2147483647", 1, "--threads"},
    {"--height-range trailing", "info {tmp}/lf.pfm --height-range 0:1:2", 1, "--height-range '0:1:2'"},
    {"relaxed-cone max-steps=1e9", kRender + "-t relaxed-cone --param max-steps=1e9", 1,
     "an integer 1 to 4096"},
    {"linear max-steps=1e6", kRender + "-t linear --max-steps 1000000", 1, "an integer 1 to 65536"},
    {"bench --elevations nan",
     "bench --preset quick --smoke --no-images --elevations nan --out-dir {tmp}/b", 1,
     "--elevations: 'nan' is not a finite number from -90 to 90"},
    {"bench --elevations 91",
     "bench --preset quick --smoke --no-images --elevations 91 --out-dir {tmp}/b", 1, "'91'"},
    {"bench --repeats 0", "bench --preset quick --smoke --no-images --repeats 0 --out-dir {tmp}/b",
     1, "--repeats"},
    {"bench --azimuth nan",
     "bench --preset quick --smoke --no-images --azimuth nan --out-dir {tmp}/b", 1,
     "--azimuth nan"},
    {"bench --distance inf",
     "bench --preset quick --smoke --no-images --distance inf --out-dir {tmp}/b", 1,
     "--distance inf"},
    {"bench --caps 1.5", "bench --preset quick --smoke --no-images --caps 1.5 --out-dir {tmp}/b", 1,
     "is not an integer"},
    {"bench --size overflow",
     "bench --preset quick --smoke --no-images --size 4294967312x16 --out-dir {tmp}/b", 1,
     "--size '4294967312x16'"},
    // Class 8: PFM headers with CRLF or comments read as the LF one.
    {"PFM LF", "info {tmp}/lf.pfm", 0, "mean 0.4306"},
    {"PFM CRLF", "info {tmp}/crlf.pfm", 0, "mean 0.4306"},
    {"PFM comment", "info {tmp}/comment.pfm", 0, "mean 0.4306"},
    {"rays from 1e20", "trace " + kMap + " --rays {tmp}/far20.csv", 3,
     "far20.csv:1: origin coordinate 1e+20 is too far"},
    // Class 9: the render summary's denominators, and -q.
    {"render covered px", kRender + "--deterministic", 0, " of 256 |"},
    {"render covered note", kRender + "--deterministic", 0,
     "covered px: where the reference or the technique hits"},
    {"render json covered", kRender + "--deterministic --format json", 0, "\"covered_pixels\""},
};

TEST_F(Inputs, HostileTable) {
    for (const InputCase& c : kInputCases) {
        const Output r = relief(c.args);
        EXPECT_EQ(r.code, c.exitCode) << c.name << ": relief " << c.args << "\nstderr: " << r.err;
        EXPECT_NE((r.out + r.err).find(c.fragment), std::string::npos)
            << c.name << ": output lacks '" << c.fragment << "':\n"
            << r.out << r.err;
    }
    // Nothing of a refused bench was made.
    EXPECT_FALSE(fs::exists(tmp / "b"));
}

TEST_F(Inputs, FarRaysHitInsideTheBox) {
    const Output r = relief("trace " + kMap + " --rays {tmp}/far12.csv");
    ASSERT_EQ(r.code, 0) << r.err;
    std::istringstream lines(r.out);
    std::string header, far, near;
    std::getline(lines, header);
    std::getline(lines, far);
    std::getline(lines, near);
    auto fields = [](const std::string& line) {
        std::vector<double> v;
        std::istringstream in(line);
        for (std::string f; std::getline(in, f, ',');) v.push_back(std::strtod(f.c_str(), nullptr));
        return v;
    };
    const std::vector<double> a = fields(far), b = fields(near);
    ASSERT_EQ(a.size(), 7u);
    ASSERT_EQ(b.size(), 7u);
    EXPECT_EQ(a[0], 1.0) << far;
    EXPECT_EQ(b[0], 1.0) << near;
    for (int k = 2; k < 5; ++k) {
        EXPECT_GE(a[k], 0.0) << far;
        EXPECT_LE(a[k], 32.0) << far;
        EXPECT_NEAR(a[k], b[k], 1e-3) << far << " vs " << near;
    }
}

TEST_F(Inputs, QuietPrintsErrorsOnly) {
    for (const std::string& args :
         {"-q " + kRender + "--deterministic",
          "-q " + kRender + "-t safety-cc --param phi-max=-45 --elevation 30",
          "-q bake " + kMap + " -t cone -o {tmp}/q.exr",
          std::string("-q bench --preset quick --smoke --no-images --out-dir {tmp}/qb")}) {
        const Output r = relief(args);
        EXPECT_EQ(r.code, 0) << args << ": " << r.err;
        EXPECT_EQ(r.out, "") << args;
        EXPECT_EQ(r.err, "") << args;
    }
    const Output failed = relief("-q " + kRender + "--fov nan");
    EXPECT_EQ(failed.code, 1);
    EXPECT_NE(failed.err.find("relief: error: --fov"), std::string::npos) << failed.err;
}

// The mechanisms.

TEST(InputsUnit, OpenRegularFileRefusesEverythingElse) {
    const fs::path dir =
        fs::temp_directory_path() / ("relief_open_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    writeBytes(dir / "file", "abc");
    int64_t size = -1;
    auto file = openRegularFile((dir / "file").string(), "a test file", &size);
    ASSERT_TRUE(file) << file.error().message;
    EXPECT_EQ(size, 3);
    char buffer[4] = {};
    EXPECT_EQ(std::fread(buffer, 1, 4, file->get()), 3u);  // an ordinary blocking stream
    for (const char* name : {"fifo", "."}) {
        auto refused = openRegularFile((dir / name).string(), "a test file");
        ASSERT_FALSE(refused) << name;
        EXPECT_EQ(refused.error().kind, ErrorKind::Io);
        EXPECT_NE(refused.error().message.find("not a test file"), std::string::npos)
            << refused.error().message;
    }
    EXPECT_FALSE(openRegularFile((dir / "missing").string(), "a test file"));
    fs::remove_all(dir);
}

TEST(InputsUnit, RayParserStopsWhereTheInputGoesWrong) {
    auto nul = parseRays(std::string_view("1,1,5,0,0,-1\n1,1\0,5,0,0,-1\n", 27), "r.csv");
    ASSERT_FALSE(nul);
    EXPECT_NE(nul.error().message.find("r.csv:2: NUL byte"), std::string::npos)
        << nul.error().message;

    auto limit = parseRays("1,1,5,0,0,-1\n1,1,5,0,0,-1\n", "r.csv", 1);
    ASSERT_FALSE(limit);
    EXPECT_NE(limit.error().message.find("r.csv:2: more than 1 rays"), std::string::npos);
    EXPECT_TRUE(parseRays("1,1,5,0,0,-1\n1,1,5,0,0,-1\n", "r.csv", 2));

    auto longLine = parseRays(std::string(kMaxRayLineBytes + 1, ' '), "r.csv");
    ASSERT_FALSE(longLine);
    EXPECT_NE(longLine.error().message.find("longer than"), std::string::npos);

    auto far = parseRays("2e12,1,5,0,0,-1\n", "r.csv");
    ASSERT_FALSE(far);
    EXPECT_NE(far.error().message.find("too far for float precision"), std::string::npos);
    EXPECT_TRUE(parseRays("1e12,1,5,0,0,-1\n", "r.csv"));
}

TEST(InputsUnit, ReadRaysFromADeviceStopsAtOnce) {
    auto zero = readRays("/dev/zero");  // refused by type, never read
    ASSERT_FALSE(zero);
    EXPECT_NE(zero.error().message.find("character device"), std::string::npos);
}

TEST(InputsUnit, PfmHeaderWithCrlfAndComments) {
    const fs::path dir =
        fs::temp_directory_path() / ("relief_pfm_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    writeBytes(dir / "lf.pfm", pfm("Pf\n4 3\n-1.0\n"));
    auto reference = loadHeightfield((dir / "lf.pfm").string());
    ASSERT_TRUE(reference) << reference.error().message;
    for (const char* header : {"Pf\r\n4 3\r\n-1.0\r\n", "Pf\n# comment\n4 3\n-1.0\n",
                               "Pf # after magic\n4 # width\n3\n-1.0\n", "Pf 4 3 -1.0\n"}) {
        writeBytes(dir / "h.pfm", pfm(header));
        auto hf = loadHeightfield((dir / "h.pfm").string());
        ASSERT_TRUE(hf) << header << ": " << hf.error().message;
        ASSERT_EQ(hf->width, 4);
        ASSERT_EQ(hf->height, 3);
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) EXPECT_EQ(hf->at(i, j), reference->at(i, j)) << header;
    }
    fs::remove_all(dir);
}

TEST(InputsUnit, NearBoxMovesFarRaysInDouble) {
    auto hf = std::make_shared<const Heightfield>(*loadHeightfield("gen:fbm:32x32"));
    const Surface surface(hf, 3.2f, EdgeMode::Clamp);
    const vec3 d = glm::normalize(vec3(-1.0f));
    double offset = -1.0;
    const Ray nearRay{vec3(20.0f), d, kInfinity};
    const Ray same = surface.nearBox(nearRay, offset);
    EXPECT_EQ(offset, 0.0);
    EXPECT_EQ(same.origin, nearRay.origin);

    const Ray far{vec3(1e12f), d, kInfinity};
    const Ray moved = surface.nearBox(far, offset);
    EXPECT_GT(offset, 1e12);
    for (int a = 0; a < 3; ++a) EXPECT_LT(std::abs(moved.origin[a]), 200.0f) << a;
    EXPECT_FALSE(surface.clip(moved).empty());

    const Ray away{vec3(1e12f), -d, kInfinity};  // leaves: a miss, whatever the precision
    EXPECT_TRUE(surface.clip(surface.nearBox(away, offset)).empty());
    // Repeat: down to the z slab, x and y wrapped by whole periods.
    const Surface tiled(hf, 3.2f, EdgeMode::Repeat);
    const Ray down = tiled.nearBox(
        Ray{vec3(5.0f, 5.0f, 1e11f), glm::normalize(vec3(0.001f, 0.002f, -1.0f)), kInfinity},
        offset);
    EXPECT_GT(offset, 9e10);
    EXPECT_GE(down.origin.x, 0.0f);
    EXPECT_LT(down.origin.x, 32.0f);
    EXPECT_GE(down.origin.y, 0.0f);
    EXPECT_LT(down.origin.y, 32.0f);
    EXPECT_LT(down.origin.z, 100.0f);
    EXPECT_FALSE(tiled.clip(down).empty());
    // Not moved first, an origin beyond float precision misses rather than hits anywhere.
    EXPECT_TRUE(surface.clip(Ray{vec3(1e20f), d, kInfinity}).empty());
}

TEST(InputsUnit, CompareHitsCountsCoveredPixels) {
    Image<Hit> ref(4, 1), hits(4, 1);
    ref.pixels[0].hit = hits.pixels[0].hit = true;  // both hit, same t
    ref.pixels[1].hit = true;                       // the technique misses: wrong
    hits.pixels[2].hit = true;                      // a false hit: wrong
    for (Hit& h : hits.pixels) h.steps = 4;         // pixel 3: background, both miss
    const ErrorStats s = compareHits(hits, ref);
    EXPECT_EQ(s.pixels, 4u);
    EXPECT_EQ(s.covered, 3u);
    EXPECT_EQ(s.bothHit, 1u);
    EXPECT_EQ(s.wrong, 2u);
    EXPECT_DOUBLE_EQ(s.wrongRate(), 0.5);  // the bench's column, over every pixel
    EXPECT_DOUBLE_EQ(s.coveredWrongRate(), 2.0 / 3.0);
    EXPECT_EQ(s.coveredSteps.count, 3u);
    EXPECT_EQ(s.steps.count, 4u);
}

}  // namespace
}  // namespace relief
