// The CLI's files for scripts: `relief rays` writes the primary rays `render` traces, so that
// `relief trace` of them gives render's depth; hit files carry fetches; a per-ray tmax turns
// farther hits into misses; depth as .npy and .pfm. Pipes are in tests/output_cli_test.cpp.
#include <gtest/gtest.h>
#include <relief/io/npy.h>
#include <relief/io/ray_io.h>
#include <relief/io/read_common.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/cli_case.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using testing::CliCase;
using testing::readFile;

class CliIo : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        tmp = fs::temp_directory_path() / ("relief_cli_io_test_" + std::to_string(::getpid()));
        fs::create_directories(tmp);
        std::ofstream(tmp / "rays.csv") << "8,8,30,0.1,0.2,-1\n";
        std::ofstream(tmp / "int.npy", std::ios::binary)
            << npyPreamble(std::vector<NpyField>{{"", "<i4"}}, std::vector<int64_t>{0, 6});
    }
    static void TearDownTestSuite() { fs::remove_all(tmp); }

    static void run(const CliCase& c) { testing::runCliCase(c, tmp); }
    static int relief(const std::string& args) {
        const std::string command =
            std::string(RELIEF_CLI_PATH) + " -q " + args + " 2>" + (tmp / "stderr.txt").string();
        const int status = std::system(command.c_str());
        EXPECT_EQ(status, 0) << args << "\n" << readFile(tmp / "stderr.txt");
        return status;
    }
    static std::string path(const std::string& name) { return (tmp / name).string(); }
    static inline fs::path tmp;
};

// The data of a .npy file relief wrote, after checking its header's fields and shape.
std::string npyData(const std::string& path, std::span<const NpyField> fields,
                    const std::vector<int64_t>& shape) {
    const std::string bytes = readFile(path);
    FilePtr in(::fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "r"));
    auto header = readNpyHeader(in.get(), int64_t(bytes.size()), path);
    EXPECT_TRUE(header) << header.error().message;
    if (!header) return {};
    EXPECT_EQ(header->shape, shape) << path;
    EXPECT_EQ(header->fields.size(), fields.size()) << path;
    for (size_t k = 0; k < std::min(fields.size(), header->fields.size()); ++k) {
        EXPECT_EQ(header->fields[k].name, fields[k].name);
        EXPECT_EQ(header->fields[k].type, fields[k].type);
    }
    return bytes.substr(size_t(header->dataOffset));
}

std::vector<float> depthNpy(const std::string& path, int width, int height) {
    const NpyField f4[] = {{"", "<f4"}};
    const std::string data = npyData(path, f4, {height, width});
    std::vector<float> depth(data.size() / 4);
    std::memcpy(depth.data(), data.data(), depth.size() * 4);
    return depth;
}

struct HitRow {
    bool hit;
    float t;
    int32_t steps, fetches;
};
std::vector<HitRow> hitsNpy(const std::string& path, int64_t count) {
    const std::string data = npyData(path, kHitFields, {count});
    std::vector<HitRow> rows(data.size() / 25);
    for (size_t k = 0; k < rows.size(); ++k) {
        const char* p = data.data() + 25 * k;
        rows[k].hit = p[0] != 0;
        std::memcpy(&rows[k].t, p + 1, 4);
        std::memcpy(&rows[k].steps, p + 17, 4);
        std::memcpy(&rows[k].fetches, p + 21, 4);
    }
    return rows;
}

std::vector<std::vector<std::string>> csvRows(const std::string& path) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream lines(readFile(path));
    for (std::string line; std::getline(lines, line);) {
        rows.emplace_back();
        std::istringstream fields(line);
        for (std::string f; std::getline(fields, f, ',');) rows.back().push_back(f);
    }
    return rows;
}

const CliCase kCases[] = {
    {"trace help: formats", "trace --help", 0, "hit,t,x,y,z,steps,fetches", ""},
    {"trace help: hit dtype", "trace --help", 0, "('fetches','<i4')", ""},
    {"trace help: tmax", "trace --help", 0, "ox,oy,oz,dx,dy,dz[,tmax]", ""},
    {"render help: depth formats", "render --help", 0,
     ".pfm (grey, little endian, bottom row first)", ""},
    {"rays help", "rays --help", 0, "exactly those `render` traces", ""},
    {"help lists rays", "help", 0, "rays", ""},
    {"rays CSV on stdout", "rays gen:fbm:16x16 --size 2x2", 0, "ox,oy,oz,dx,dy,dz\n", ""},
    {"rays: bad size", "rays gen:fbm:16x16 --size 0x4 -o {tmp}/r.npy", 1, "", "--size '0x4'"},
    {"rays: no light", "rays gen:fbm:16x16 --light-elevation 30", 1, "", "--light-elevation"},
    {"rays: nan elevation", "rays gen:fbm:16x16 --elevation nan", 1, "", "--elevation"},
    {"rays into a directory", "rays gen:fbm:16x16 --size 4x4 -o {tmp}", 2, "", "is a directory"},
    {"trace: npy of ints", "trace gen:fbm:16x16 --rays {tmp}/int.npy", 3, "",
     "rays must be float32 or float64"},
    {"trace: missing npy", "trace gen:fbm:16x16 --rays {tmp}/none.npy", 2, "",
     "none.npy: cannot open"},
    {"trace: csv hits with fetches", "trace gen:fbm:16x16 --rays {tmp}/rays.csv -o -", 0,
     "hit,t,x,y,z,steps,fetches\n1,", ""},
};

TEST_F(CliIo, Table) {
    for (const CliCase& c : kCases) run(c);
}

// `relief rays` + `relief trace` of them = `render` of the view: the same hits, bit for bit
// through .npy, to the CSV's seven digits through CSV; and the PFM depth equals the .npy one.
TEST_F(CliIo, RaysThenTraceIsRender) {
    const std::string map = "gen:peaks6:48x48 --depth-ratio 0.15";
    const std::string view = " --elevation 33 --azimuth 20 --distance 1.1 --size 32x24";
    for (const std::string technique : {"exact", "cone"}) {
        relief("rays " + map + view + " -o " + path("r.npy"));
        relief("rays " + map + view + " -o " + path("r.csv"));
        relief("trace " + map + " -t " + technique + " --rays " + path("r.npy") + " -o " +
               path("h.npy"));
        relief("trace " + map + " -t " + technique + " --rays " + path("r.csv") + " -o " +
               path("h.csv"));
        relief("render " + map + view + " -t " + technique + " -o " + path("c.png") +
               " --depth-out " + path("d.npy"));
        relief("render " + map + view + " -t " + technique + " -o " + path("c.png") +
               " --depth-out " + path("d.pfm"));
        const std::vector<float> depth = depthNpy(path("d.npy"), 32, 24);
        const std::vector<HitRow> hits = hitsNpy(path("h.npy"), 32 * 24);
        const auto csv = csvRows(path("h.csv"));
        ASSERT_EQ(depth.size(), hits.size());
        ASSERT_EQ(csv.size(), hits.size() + 1);
        EXPECT_EQ(csv[0],
                  (std::vector<std::string>{"hit", "t", "x", "y", "z", "steps", "fetches"}));
        int covered = 0;
        for (size_t k = 0; k < hits.size(); ++k) {
            EXPECT_EQ(hits[k].hit ? hits[k].t : kInfinity, depth[k]) << technique << " pixel " << k;
            ASSERT_EQ(csv[k + 1].size(), 7u);
            EXPECT_EQ(csv[k + 1][0] == "1", hits[k].hit) << technique << " pixel " << k;
            if (hits[k].hit)
                EXPECT_NEAR(std::stod(csv[k + 1][1]), depth[k], 1e-6 * depth[k]);
            else
                EXPECT_EQ(csv[k + 1][1], "inf");
            EXPECT_EQ(std::stoi(csv[k + 1][5]), hits[k].steps);
            EXPECT_EQ(std::stoi(csv[k + 1][6]), hits[k].fetches);
            if (hits[k].hit) {
                ++covered;
                EXPECT_GT(hits[k].fetches, 0) << technique << " pixel " << k;
            }
        }
        EXPECT_GT(covered, 100) << technique;  // the view looks at the relief
        auto file = FileReader::open(path("d.pfm"));
        ASSERT_TRUE(file) << file.error().message;
        auto decoder = makePfmHeightDecoder(*file, ChannelSelect::Luminance);
        auto pfm = decodeImage(*decoder, file->path(), kDefaultMaxSamples);
        ASSERT_TRUE(pfm) << pfm.error().message;
        EXPECT_EQ(pfm->image.pixels, depth) << technique;
    }
}

// tmax is measured along the ray as given, also when a far origin is first brought to the box.
TEST_F(CliIo, TmaxTurnsFartherHitsIntoMisses) {
    std::ofstream(tmp / "tmax.csv") << "ox,oy,oz,dx,dy,dz,tmax\n"
                                       "8,8,30,0,0,-1\n"
                                       "8,8,30,0,0,-1,20\n"
                                       "8,8,30,0,0,-1,40\n"
                                       "1e12,1e12,1e12,-1,-1,-1,1e12\n"
                                       "1e12,1e12,1e12,-1,-1,-1,1e13\n";
    for (const std::string technique : {"exact", "linear"}) {
        relief("trace gen:fbm:32x32 -t " + technique + " --rays " + path("tmax.csv") + " -o " +
               path("t.csv"));
        const auto rows = csvRows(path("t.csv"));
        ASSERT_EQ(rows.size(), 6u);
        const std::vector<std::string> expected = {"1", "0", "1", "0", "1"};
        for (size_t k = 0; k < expected.size(); ++k)
            EXPECT_EQ(rows[k + 1][0], expected[k]) << technique << " ray " << k;
        EXPECT_EQ(rows[3][1], rows[1][1]);  // within tmax: the hit of the ray without one
        EXPECT_EQ(rows[2][1], "inf");
        EXPECT_EQ(rows[2][2], "nan");
    }
}

// What NumPy writes relief reads, and what relief writes NumPy reads (skipped without numpy).
TEST_F(CliIo, NumpyReadsAndWritesTheSameFiles) {
    if (std::system("/usr/bin/python3 -c 'import numpy' 2>/dev/null") != 0)
        GTEST_SKIP() << "no /usr/bin/python3 with numpy";
    const std::string script = path("interop.py");
    std::ofstream(script)
        << "import numpy as np, subprocess, sys\n"
           "relief, tmp = sys.argv[1], sys.argv[2]\n"
           "r = np.array([[8, 8, 30, 0, 0, -1, np.inf], [8, 8, 30, 0, 0, -1, 1]])\n"
           "np.save(tmp + '/np.npy', r)\n"
           "subprocess.run([relief, 'trace', 'gen:fbm:32x32', '--rays', tmp + "
           "'/np.npy', '-o', tmp + '/hits.npy'], check=True)\n"
           "h = np.load(tmp + '/hits.npy')\n"
           "assert h.dtype.names == ('hit', 't', 'x', 'y', 'z', 'steps', "
           "'fetches'), h.dtype\n"
           "assert h.dtype['hit'] == np.bool_ and h.shape == (2,), h\n"
           "assert h['hit'].tolist() == [True, False], h\n"
           "assert np.isinf(h['t'][1]) and np.isnan(h['x'][1]), h\n"
           "subprocess.run([relief, 'rays', 'gen:fbm:32x32', '--size', '5x4', "
           "'-o', tmp + '/rays.npy'], check=True)\n"
           "rays = np.load(tmp + '/rays.npy')\n"
           "assert rays.dtype == np.float32 and rays.shape == (20, 6), rays\n"
           "assert np.allclose(np.linalg.norm(rays[:, 3:], axis=1), 1), rays\n";
    const int status = std::system(("/usr/bin/python3 " + script + " " + RELIEF_CLI_PATH + " " +
                                    tmp.string() + " 2>" + path("py.txt"))
                                       .c_str());
    EXPECT_EQ(status, 0) << readFile(tmp / "py.txt");
}

}  // namespace
}  // namespace relief
