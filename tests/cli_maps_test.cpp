// Issue 22, classes 3 and 7, through the CLI: damaged or edited map files are refused naming the
// file, and no option is silently ignored (bake, --maps, generator sources, twice-given
// parameters). One row per hostile input: arguments, exit code, a fragment of stderr.
#include <support/cli_case.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace {

namespace fs = std::filesystem;

using relief::testing::CliCase;

// {tmp} is this suite's temporary folder; no case checks stdout.
const CliCase kMapsCases[] = {
    {"baked maps are used", "trace gen:fbm:24x24 -t cone --maps {tmp}/m.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 0, "", ""},
    // Class 3: damage and hand edits.
    {"flipped data byte", "trace gen:fbm:24x24 -t quadtree --maps {tmp}/flip.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 3, "", "flip.exr: map file damaged: part 'quadtree/level"},
    {"nan source depth", "trace gen:fbm:24x24 -t quadtree --depth 7 --maps {tmp}/nan.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 3, "", "nan.exr: map file damaged: relief.source.depth 'nan"},
    {"edge edited", "trace gen:fbm:24x24 -t quadtree --maps {tmp}/edge.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 3, "", "relief.source.edge 'cramp' is not clamp or repeat"},
    {"missing map file", "trace gen:fbm:24x24 -t cone --maps {tmp}/none.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 2, "", "none.exr: cannot open"},
    // Maps baked with other parameters: exit 3 for every row, as docs/robustness.md says.
    {"cone bits differ", "trace gen:fbm:24x24 -t cone --param bits=16 --maps {tmp}/m.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 3, "", "m.exr: cone: baked maps have bits=32"},
    {"safety phi-max differs", "trace gen:fbm:24x24 -t safety-cc --phi-max -30 --maps {tmp}/m.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 3, "", "m.exr: safety-cc: maps were baked with phi-max 90"},
    // Class 7: options never silently ignored.
    {"maps for a row without maps", "trace gen:fbm:24x24 -t exact --maps {tmp}/none.exr --rays {tmp}/rays.csv -o {tmp}/h.csv", 5, "", "--maps: exact reads no maps"},
    {"raw with a generator", "trace gen:fbm:24x24 --raw 24x24:u8 --rays {tmp}/rays.csv -o {tmp}/h.csv", 1, "", "gen:fbm:24x24: --raw describes a file; a generator reads none"},
    {"height range with a generator", "bake gen:fbm:24x24 --maps cone --height-range 0:1 -o {tmp}/x.exr", 1, "", "--height-range describes a file"},
    {"channel with a generator", "trace gen:fbm:24x24 --channel r --rays {tmp}/rays.csv -o {tmp}/h.csv", 1, "", "--channel describes a file"},
    {"bake twin techniques", "bake gen:fbm:24x24 --maps cone,cone -o {tmp}/x.exr", 1, "", "bake: --maps names 'cone' twice"},
    {"bake unknown parameter", "bake gen:fbm:24x24 --maps cone --param nonsense=1 -o {tmp}/x.exr", 1, "", "technique 'cone' has no parameter 'nonsense'"},
    {"bake iteration cap", "bake gen:fbm:24x24 --maps cone --max-steps 5 -o {tmp}/x.exr", 1, "", "bake: cone: parameter 'max-steps' does not change the maps"},
    {"bake tracer-only parameter", "bake gen:fbm:24x24 --maps cone,quadtree --param ascend=0 -o {tmp}/x.exr", 1, "", "bake: quadtree: parameter 'ascend' does not change the maps"},
    {"parameter given twice", "trace gen:fbm:24x24 -t cone --param bits=16 --param bits=8 --rays {tmp}/rays.csv -o {tmp}/h.csv", 1, "", "cone: parameter 'bits' is given twice"},
    {"role option and its parameter", "trace gen:fbm:24x24 -t cone --max-steps 5 --param max-steps=6 --rays {tmp}/rays.csv -o {tmp}/h.csv", 1, "", "parameter 'max-steps' is given twice"},
};

class CliMaps : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir = fs::temp_directory_path() / ("relief_cli_maps_" + std::to_string(::getpid()));
        fs::create_directories(dir);
        std::ofstream(dir / "rays.csv") << "8,8,30,0.1,0.2,-1\n-5,5,1,1,0,0\n";
        ASSERT_EQ(relief("bake gen:fbm:24x24 --maps cone,quadtree,safety-cc -o {dir}/m.exr"), 0);
        std::ifstream in(dir / "m.exr", std::ios::binary);
        const std::string maps(std::istreambuf_iterator<char>(in), {});
        // The pyramid's top levels hold the highest sample, 1 × depth 2.4, stored uncompressed
        // (the case: a flip that decompresses fine and changes a value).
        const float top = 2.4f;
        const size_t at = maps.rfind(std::string(reinterpret_cast<const char*>(&top), sizeof top));
        ASSERT_NE(at, std::string::npos);
        std::string flip = maps;
        flip[at] ^= 0x04;
        write("flip.exr", flip);
        write("nan.exr", replaced(maps, "2.4000001", "nan      "));  // the stored depth, same length
        write("edge.exr", replaced(maps, "clamp", "cramp"));
    }
    static void TearDownTestSuite() { fs::remove_all(dir); }

    static std::string replaced(std::string text, const std::string& from, const std::string& to) {
        for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
            text.replace(at, from.size(), to);
        return text;
    }
    static void write(const char* name, const std::string& bytes) {
        std::ofstream(dir / name, std::ios::binary) << bytes;
    }
    // Exit code of `relief ARGS` with stderr in {dir}/err.txt.
    static int relief(const std::string& args) {
        const std::string line = std::string(RELIEF_CLI_PATH) + " " + replaced(args, "{dir}", dir.string()) +
                                 " >" + (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
        const int status = std::system(line.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    static inline fs::path dir;
};

TEST_F(CliMaps, Table) {
    for (const CliCase& c : kMapsCases) {
        relief::testing::runCliCase(c, dir);
        // relief's own message only: one line, nothing from a library before it.
        if (c.exitCode != 0) {
            const std::string err = relief::testing::readFile(dir / "stderr.txt");
            EXPECT_EQ(err.rfind("relief: error: ", 0), 0u) << c.name << ":\n" << err;
        }
    }
}

}  // namespace
