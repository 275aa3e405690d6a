// Issue 22 class 5: one memory budget (--max-memory), checked before large allocations. Unit
// tests of the parsing and of reserveMemory, then the hostile-input cases as a table.
#include <relief/core/memory_budget.h>

#include "support/cli_case.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace relief {
namespace {

namespace fs = std::filesystem;

TEST(MemoryBudget, ParsesSizes) {
    EXPECT_EQ(*parseMemorySize("1048576"), int64_t(1) << 20);
    EXPECT_EQ(*parseMemorySize("512M"), int64_t(512) << 20);
    EXPECT_EQ(*parseMemorySize("512m"), int64_t(512) << 20);
    EXPECT_EQ(*parseMemorySize("4G"), int64_t(4) << 30);
    EXPECT_EQ(*parseMemorySize("4GB"), int64_t(4) << 30);
    EXPECT_EQ(*parseMemorySize("2048K"), int64_t(2) << 20);
    EXPECT_EQ(*parseMemorySize("1024G"), int64_t(1) << 40);
}

TEST(MemoryBudget, RefusesMalformedSizes) {
    for (const char* text : {"", "G", "-1G", "0", "1.5G", "12Q", "4 G", "4GG", "1k", "1000",
                             "99999999999999999999", "9999999999999G"}) {
        const auto parsed = parseMemorySize(text);
        ASSERT_FALSE(parsed) << text;
        EXPECT_EQ(parsed.error().kind, ErrorKind::BadArgument) << text;
        EXPECT_NE(parsed.error().message.find("--max-memory"), std::string::npos) << text;
    }
}

TEST(MemoryBudget, DefaultIsHalfOfPhysicalMemory) {
    const int64_t physical = int64_t(::sysconf(_SC_PHYS_PAGES)) * ::sysconf(_SC_PAGESIZE);
    EXPECT_EQ(defaultMemoryBudget(), physical / 2);
}

TEST(MemoryBudget, ReserveChecksTheEstimateAgainstTheBudget) {
    const int64_t saved = memoryBudget();
    setMemoryBudget(int64_t(1) << 30);
    EXPECT_TRUE(reserveMemory(int64_t(1) << 30, "exactly the budget"));
    EXPECT_TRUE(reserveMemory(0, "nothing"));
    const Status over = reserveMemory((int64_t(3) << 30) + 1, "big.png: decoding");
    ASSERT_FALSE(over);
    EXPECT_EQ(over.error().kind, ErrorKind::InvalidInput);
    EXPECT_NE(over.error().message.find("big.png: decoding"), std::string::npos);
    EXPECT_NE(over.error().message.find("3.0 GiB"), std::string::npos);
    EXPECT_NE(over.error().message.find("1.0 GiB"), std::string::npos);
    EXPECT_NE(over.error().message.find("--max-memory 4G"), std::string::npos);
    EXPECT_FALSE(reserveMemory(-1, "an overflowed estimate"));
    setMemoryBudget(saved);
}

// --- the CLI cases -----------------------------------------------------------------------------

using MemoryCase = testing::CliCase;
using testing::readFile;

void be32(std::string& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out += char((v >> shift) & 0xff);
}

void chunk(std::string& png, const char* type, const std::string& data) {
    be32(png, uint32_t(data.size()));
    const std::string typed = type + data;
    png += typed;
    be32(png, uint32_t(crc32(0, reinterpret_cast<const Bytef*>(typed.data()), uInt(typed.size()))));
}

// A PNG whose header says W×H at `depth` bits of colour type `type`, with `raw` (filter bytes and
// pixels, as many as given) deflated as its image data.
std::string makePng(uint32_t w, uint32_t h, int depth, int type, bool interlaced,
                    const std::string& raw) {
    std::string png = "\x89PNG\r\n\x1a\n", ihdr;
    be32(ihdr, w);
    be32(ihdr, h);
    ihdr += {char(depth), char(type), 0, 0, char(interlaced ? 1 : 0)};
    chunk(png, "IHDR", ihdr);
    uLongf size = compressBound(uLong(raw.size()));
    std::string packed(size, '\0');
    compress2(reinterpret_cast<Bytef*>(packed.data()), &size,
              reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 9);
    packed.resize(size);
    chunk(png, "IDAT", packed);
    chunk(png, "IEND", "");
    return png;
}

class MemoryCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        tmp = fs::temp_directory_path() / ("relief_memory_test_" + std::to_string(::getpid()));
        fs::create_directories(tmp);
        std::ofstream(tmp / "rays.csv") << "ox,oy,oz,dx,dy,dz\n8,8,30,0.1,0.2,-1\n";
        // The file: 16384x16384 16-bit RGBA, interlaced, a few bytes of image data.
        std::ofstream(tmp / "huge.png", std::ios::binary)
            << makePng(16384, 16384, 16, 6, true, std::string(4, '\0'));
        // The same claim for an 8-bit grey image, and a 1-bit palette-free grey one.
        std::ofstream(tmp / "huge-grey.png", std::ios::binary)
            << makePng(60000, 60000, 8, 0, false, std::string(100, '\0'));
        // A whole, valid 2048x2048 16-bit RGBA interlaced image of zeros (it compresses ~1000:1):
        // decoding needs 2048*2048*(8 + 4) bytes = 48 MiB.
        std::string raw;
        for (int pass = 0; pass < 7; ++pass) {
            static const int x0[] = {0, 4, 0, 2, 0, 1, 0}, dx[] = {8, 8, 4, 4, 2, 2, 1};
            static const int y0[] = {0, 0, 4, 0, 2, 0, 1}, dy[] = {8, 8, 8, 4, 4, 2, 2};
            const int cols = (2048 - x0[pass] + dx[pass] - 1) / dx[pass];
            const int rows = (2048 - y0[pass] + dy[pass] - 1) / dy[pass];
            for (int r = 0; r < rows; ++r) raw += std::string(1 + size_t(cols) * 8, '\0');
        }
        std::ofstream(tmp / "zeros.png", std::ios::binary) << makePng(2048, 2048, 16, 6, true, raw);
        // Highly compressible but valid: 1-bit grey, 4096x4096 of zeros (must not be refused by
        // the data-size bound, which counts the bits stored in the file).
        std::string bits;
        for (int r = 0; r < 4096; ++r) bits += std::string(1 + 4096 / 8, '\0');
        std::ofstream(tmp / "bits.png", std::ios::binary) << makePng(4096, 4096, 1, 0, false, bits);
    }
    static void TearDownTestSuite() { fs::remove_all(tmp); }

    static void run(const MemoryCase& c) { testing::runCliCase(c, tmp); }
    static inline fs::path tmp;
};

const MemoryCase kMemoryCases[] = {
    // Headers that claim far more pixels than their data can hold: refused before any buffer.
    {"interlaced 16-bit RGBA claim", "info {tmp}/huge.png", 3, "",
     "cannot hold 16384x16384 pixels of 64 bits (decoding would need about 3.0 GiB)"},
    {"same under a budget", "info {tmp}/huge.png --max-memory 1G", 3, "", "3.0 GiB"},
    {"grey claim", "info {tmp}/huge-grey.png --max-samples 4000000000", 3, "", "cannot hold 60000x60000"},
    {"as a colour map", "render gen:fbm:16x16 --color {tmp}/huge.png --size 8x8 -o {tmp}/c.png", 3, "", "cannot hold 16384x16384"},
    // A valid image over the budget: the estimate, the budget and the option in the message.
    {"valid PNG over the budget", "info {tmp}/zeros.png --max-memory 32M", 3, "",
     "decoding 2048x2048 pixels: needs about 48.0 MiB, over the memory budget of 32.0 MiB (raise it with --max-memory"},
    {"valid PNG under the budget", "info {tmp}/zeros.png --max-memory 128M", 0, "2048x2048 samples", ""},
    {"1-bit PNG of zeros", "info {tmp}/bits.png", 0, "4096x4096 samples", ""},
    {"real PNG", "info {src}/data/colorado-elevation-400.png --max-memory 16M", 0, "400x400", ""},
    {"colour map over the budget", "render gen:fbm:16x16 --color {src}/data/earth-topology-2048x1024.png --size 8x8 -o {tmp}/j.png --max-memory 4M", 3, "", "decoding 2048x1024 pixels: needs about 6.0 MiB, over the memory budget of 4.0 MiB"},
    // The renderer: refused before its rays and hits are allocated, no folder left.
    {"render the documented maximum", "render gen:fbm:64x64 --size 16384x16384 --max-memory 1G -o {tmp}/r.png", 3, "",
     "render --size 16384x16384 with 1 technique(s): needs about 21.0 GiB, over the memory budget of 1.0 GiB"},
    {"render several", "render gen:fbm:64x64 --size 8192x8192 -t exact,linear --shadows --max-memory 2G --out-dir {tmp}/never", 3, "", "needs about 10.4 GiB"},
    {"render normal", "render gen:fbm:32x32 --size 40x30 --max-memory 64M -o {tmp}/ok.png --deterministic", 0, "| exact | exact |", ""},
    // info: the generator and the statistics.
    {"info generator over the budget", "info gen:fbm:8192x8192 --max-memory 128M", 3, "", "gen:fbm:8192x8192: generating: needs about 256.0 MiB"},
    {"info statistics over the budget", "info gen:fbm:2048x2048 --max-memory 64M", 3, "",
     "statistics of 2048x2048 samples: needs about 112.0 MiB"},
    {"info normal", "info gen:fbm:256x256 --max-memory 16M", 0, "256x256 samples", ""},
    // Other commands take the option too.
    {"trace takes it", "trace gen:fbm:8192x8192 --max-memory 64M --rays {tmp}/rays.csv", 3, "", "generating"},
    {"bake takes it", "bake gen:fbm:8192x8192 --maps cone --max-memory 64M -o {tmp}/m.exr", 3, "", "generating"},
    // Map builders, through the registry row's estimate.
    {"bake over the budget", "bake gen:fbm:4096x4096 --maps safety-cc --max-memory 1G -o {tmp}/s.exr", 3, "",
     "safety-cc: building maps for 4096x4096 texels: needs about 3.0 GiB"},
    {"built maps over the budget", "trace gen:fbm:4096x4096 -t qdm --max-memory 256M --rays {tmp}/rays.csv", 3, "",
     "qdm: building maps for 4096x4096 texels"},
    {"render builds maps too", "render gen:fbm:2048x2048 -t cone --size 8x8 --max-memory 64M -o {tmp}/cone.png", 3, "",
     "cone: building maps for 2048x2048 texels"},
    {"maps under the budget", "bake gen:fbm:64x64 --maps cone,qdm,safety-cc --max-memory 16M -o {tmp}/ok.exr --deterministic", 0, "wrote", ""},
    // The option's own values.
    {"bad size", "info gen:fbm:8x8 --max-memory 12Q", 1, "", "--max-memory '12Q'"},
    {"too small", "info gen:fbm:8x8 --max-memory 1000", 1, "", "at least 1M"},
    {"negative", "info gen:fbm:8x8 --max-memory -1G", 1, "", "relief: error:"},
    {"help names the default", "info --help", 0, "half of physical memory", ""},
};

TEST_F(MemoryCli, Cases) {
    for (const MemoryCase& c : kMemoryCases) run(c);
    EXPECT_FALSE(fs::exists(tmp / "never")) << "a refused render made its --out-dir";
}

}  // namespace
}  // namespace relief
