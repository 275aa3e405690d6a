// CLI tests as data: command line, expected exit code, expected fragments of stdout / stderr.
#include "support/cli_case.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

using relief::testing::CliCase;
using relief::testing::readFile;

class Cli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        tmp = fs::temp_directory_path() / ("relief_cli_test_" + std::to_string(::getpid()));
        fs::create_directories(tmp);
        std::ofstream(tmp / "rays.csv") << "ox,oy,oz,dx,dy,dz\n8,8,30,0.1,0.2,-1\n-5,5,1,1,0,0\n";
        std::ofstream(tmp / "nan.csv") << "1,2,3,nan,0,-1\n";
        std::ofstream(tmp / "short.csv") << "1,2,3,0,-1\n";
        std::ofstream(tmp / "zero.csv") << "1,2,3,0,0,0\n";
        std::ofstream(tmp / "garbage.png") << "this is not an image at all";
        std::ofstream(tmp / "empty.png");
        const std::string png = readFile(fs::path(RELIEF_SOURCE_DIR) / "data/colorado-elevation-400.png");
        std::ofstream(tmp / "truncated.png", std::ios::binary) << png.substr(0, png.size() / 2);
        std::ofstream(tmp / "raw.bin", std::ios::binary) << std::string(100, '\x10');
    }
    static void TearDownTestSuite() { fs::remove_all(tmp); }

    static void run(const CliCase& c) { relief::testing::runCliCase(c, tmp); }
    static inline fs::path tmp;
};

const CliCase kCases[] = {
    // Working commands.
    {"trace exact", "trace gen:peaks6:32x32 --rays {tmp}/rays.csv", 0, "hit,t,x,y,z,steps,fetches\n1,", ""},
    {"trace linear", "trace gen:peaks6:32x32 -t linear --max-steps 16 --param binary-steps=4 --rays {tmp}/rays.csv -o -", 0, "hit,t", ""},
    {"info text", "info gen:fbm:40x30", 0, "40x30 samples", ""},
    {"info json", "info gen:ramp:8x8 --format json", 0, "\"width\": 8", ""},
    {"info real map", "info {src}/data/colorado-elevation-400.png", 0, "400x400", ""},
    {"render", "render gen:peaks6:32x32 --size 40x30 -o {tmp}/r.png --deterministic", 0, "| exact | exact |", ""},
    {"render all", "render gen:walls:24x24 -t all --size 32x24 --out-dir {tmp}/all --format json --deterministic", 0, "\"technique\": \"parallax\"", ""},
    {"version", "--version", 0, "(tracer ISA: ", ""},
    {"isa baseline", "trace gen:peaks6:32x32 --isa baseline --rays {tmp}/rays.csv", 0, "hit,t,x,y,z,steps,fetches\n1,", ""},
    {"isa auto", "trace gen:peaks6:32x32 --isa auto --rays {tmp}/rays.csv", 0, "hit,t,x,y,z,steps,fetches\n1,", ""},
    {"info isa", "info gen:fbm:40x30", 0, "tracer ISA: ", ""},
    {"phi-max warning", "render gen:fbm:32x32 -t safety-cc --param phi-max=-45 --size 32x24 --elevation 30 -o {tmp}/w.png --deterministic", 0, "| safety-cc | exact |", "outside the maps' viewing-angle restriction"},
    // The visibility-curve renderer and the sphere take the one render path.
    {"render curves", "render gen:sine:32x32 -t curves --size 40x30 -o {tmp}/c.png --depth-out {tmp}/c.exr --deterministic", 0, "| curves | 2 | 0.05 |", ""},
    {"curves epsilon param", "render gen:sine:32x32 -t curves --param epsilon=0.01 --param samples=4 --size 40x30 --out-dir {tmp}/curves --deterministic", 0, "| curves | 4 | 0.01 |", ""},
    {"curves json", "render gen:sine:32x32 -t curves,exact --size 40x30 --out-dir {tmp}/curves2 --format json --deterministic", 0, "\"visibility_curves\":", ""},
    {"sphere curves", "render gen:sine:32x16 --depth 2 --surface sphere --radius 6 -t curves --size 40x30 --out-dir {tmp}/sphere --deterministic", 0, "on the sphere", ""},
    {"sphere exact", "render gen:sine:32x16 --depth 2 --surface sphere -t exact --size 40x30 -o {tmp}/se.png --steps-out {tmp}/se-steps.png --deterministic", 0, "| exact | exact |", ""},
    {"bake and use maps", "bake gen:fbm:24x24 --maps quadtree,cone -o {tmp}/m.exr --deterministic", 0, "wrote", ""},
    {"use baked maps", "trace gen:fbm:24x24 -t quadtree --maps {tmp}/m.exr --rays {tmp}/rays.csv", 0, "hit,t", ""},
    {"stale maps refused", "trace gen:fbm:24x24:9 -t cone --maps {tmp}/m.exr --rays {tmp}/rays.csv", 3, "", "stale maps"},
    // Bad arguments: exit 1.
    {"unknown technique", "trace gen:flat:8x8 -t nope --rays {tmp}/rays.csv", 1, "", "unknown technique 'nope'"},
    {"unknown isa", "trace gen:flat:8x8 --isa avx9 --rays {tmp}/rays.csv", 1, "", "unknown ISA 'avx9'"},
    {"unknown option", "trace gen:flat:8x8 --frobnicate --rays {tmp}/rays.csv", 1, "", "relief: error:"},
    {"no command", "", 1, "", "relief: error:"},
    {"unknown generator", "info gen:mountains:8x8", 1, "", "unknown generator 'mountains'"},
    {"bad generator spec", "info gen:fbm:8by8", 1, "", "gen:NAME:WxH"},
    {"unknown param", "trace gen:flat:8x8 -t linear --param warp=2 --rays {tmp}/rays.csv", 1, "", "no parameter 'warp'"},
    {"param out of range", "trace gen:flat:8x8 -t linear --max-steps 0 --rays {tmp}/rays.csv", 1, "", "out of range"},
    {"bad param syntax", "trace gen:flat:8x8 -t linear --param binary-steps --rays {tmp}/rays.csv", 1, "", "NAME=NUMBER"},
    {"bad edge", "info gen:flat:8x8 --edge mirror", 1, "", "relief: error:"},
    {"negative depth", "trace gen:flat:8x8 --depth -3 --rays {tmp}/rays.csv", 1, "", "depth"},
    {"bad image size", "render gen:flat:8x8 --size 0x10 -o {tmp}/x.png", 1, "", "--size"},
    {"render without output", "render gen:flat:8x8", 1, "", "-o FILE.png"},
    {"bad height range", "info gen:flat:8x8 --height-range 5:1", 1, "", "--height-range"},
    {"bad raw layout", "info {tmp}/raw.bin --raw 10x10:u12", 1, "", "u8, u16 or f32"},
    {"epsilon option gone", "render gen:sine:16x16 -t curves --epsilon 0.1 --size 8x8 -o {tmp}/x.png", 1, "", "--epsilon"},
    {"radius without sphere", "render gen:sine:16x16 -t curves --radius 5 --size 8x8 -o {tmp}/x.png", 1, "", "--radius"},
    {"curves samples refused by trace", "trace gen:flat:8x8 -t curves --param samples=4 --rays {tmp}/rays.csv", 1, "", "image renderer's"},
    {"curves angle-step refused", "render gen:sine:16x16 -t curves --param angle-step=0.01 --size 8x8 -o {tmp}/x.png", 1, "", "per-ray tracer only"},
    // I/O errors: exit 2.
    {"missing heightfield", "info {tmp}/does-not-exist.png", 2, "", "does-not-exist.png"},
    {"missing ray file", "trace gen:flat:8x8 --rays {tmp}/none.csv", 2, "", "none.csv"},
    {"output folder missing", "render gen:flat:8x8 --size 8x8 -o {tmp}/no/such/dir/x.png", 2, "", "does not exist"},
    // Invalid input: exit 3.
    {"zero size generator", "info gen:fbm:0x10", 3, "", "invalid size"},
    {"absurd size", "info gen:fbm:100000x100000", 3, "", "exceeds the limit"},
    {"garbage image", "info {tmp}/garbage.png", 3, "", "garbage.png"},
    {"empty image", "info {tmp}/empty.png", 3, "", "empty.png"},
    {"truncated png", "info {tmp}/truncated.png", 3, "", "truncated.png"},
    {"raw wrong size", "info {tmp}/raw.bin --raw 20x20:u8", 3, "", "raw.bin"},
    {"nan in rays", "trace gen:flat:8x8 --rays {tmp}/nan.csv", 3, "", "nan.csv:1: non-finite"},
    {"short ray line", "trace gen:flat:8x8 --rays {tmp}/short.csv", 3, "", "short.csv:1: expected six numbers"},
    {"zero direction", "trace gen:flat:8x8 --rays {tmp}/zero.csv", 3, "", "zero or unusable direction"},
    // Unsupported: exit 5.
    {"sphere refused", "render gen:sine:16x16 -t cone --surface sphere --size 8x8 -o {tmp}/x.png", 5, "", "'cone' cannot trace the sphere (--surface sphere takes: exact, curves)"},
    {"curves gl refused", "render gen:sine:16x16 -t curves --backend gl --size 8x8 -o {tmp}/x.png", 5, "", "runs on the CPU only"},
    {"sphere gl refused", "render gen:sine:16x16 -t exact --surface sphere --backend gl --size 8x8 -o {tmp}/x.png", 5, "", "runs on the CPU only"},
    {"curves shadows refused", "render gen:sine:16x16 -t curves --shadows --size 8x8 -o {tmp}/x.png", 5, "", "--shadows"},
    {"curves maps refused", "render gen:sine:16x16 -t curves --maps {tmp}/m.exr --size 8x8 -o {tmp}/x.png", 5, "", "--maps: curves reads no maps"},
    {"sphere maps refused", "render gen:sine:16x16 -t exact --surface sphere --maps {tmp}/m.exr --size 8x8 -o {tmp}/x.png", 5, "", "--maps"},
    {"sphere cap refused", "render gen:sine:16x16 -t exact --surface sphere --max-steps 10 --size 8x8 -o {tmp}/x.png", 5, "", "no iteration cap"},
    {"sphere repeat refused", "render gen:sine:16x16 -t curves --surface sphere --edge repeat --size 8x8 -o {tmp}/x.png", 5, "", "--edge"},
    {"curves repeat refused", "render gen:sine:16x16 -t curves --edge repeat --size 8x8 -o {tmp}/x.png", 5, "", "--edge clamp"},
    // The preview shading (the default) and the diagnostic look; the bricks' own colour map.
    {"bricks preview", "render gen:bricks:64x64 --color gen --edge repeat --exposure 0.5 --specular 0.3 --smooth-normals --shadows --size 32x24 -o {tmp}/bricks.png --deterministic", 0, "| exact | exact |", ""},
    {"bricks diagnostic", "render gen:bricks:64x64:3 --color gen --shading diagnostic --smooth-normals --size 32x24 -o {tmp}/bricksd.png --deterministic", 0, "| exact | exact |", ""},
    {"exposure needs preview", "render gen:flat:8x8 --shading diagnostic --exposure 1 --size 8x8 -o {tmp}/x.png", 1, "", "--exposure: read by --shading preview only"},
    {"bad shading", "render gen:flat:8x8 --shading pretty --size 8x8 -o {tmp}/x.png", 1, "", "--shading"},
    {"no generated colour", "render gen:fbm:8x8 --color gen --size 8x8 -o {tmp}/x.png", 1, "", "generator 'fbm' has no colour map (generators with one: bricks)"},
    {"generated colour of a file", "render {src}/data/colorado-elevation-400.png --color gen --size 8x8 -o {tmp}/x.png", 1, "", "a generated colour map needs a generator source"},
    {"generated colour of a window", "render gen:bricks:32x32@crop=0,0,16,16 --color gen --size 8x8 -o {tmp}/x.png", 5, "", "--color gen"},
    {"curves refuse the preview", "render gen:sine:16x16 -t curves --shading preview --size 8x8 -o {tmp}/x.png", 5, "", "--shading: the visibility-curve renderer draws the diagnostic shading only"},
    {"sphere refuses smooth normals", "render gen:sine:32x16 --depth 2 --surface sphere -t exact --smooth-normals --size 8x8 -o {tmp}/x.png", 5, "", "--smooth-normals"},
    {"curves draw the diagnostic look by default", "render gen:sine:32x32 -t curves,exact --size 16x12 --out-dir {tmp}/mixed --deterministic", 0, "| curves | 2 |", ""},
};

TEST_F(Cli, Table) {
    for (const CliCase& c : kCases) run(c);
}

// --max-steps, --phi-max and --visibility set the parameter with that role (DESIGN §3 names);
// an option no selected technique has is an error, never ignored.
const CliCase kRoleCases[] = {
    {"phi-max", "trace gen:fbm:32x32 -t safety-cc --phi-max -45 --rays {tmp}/rays.csv", 0, "hit,t", ""},
    {"phi-max out of range", "trace gen:fbm:32x32 -t safety-sd --phi-max 95 --rays {tmp}/rays.csv", 1, "", "out of range"},
    {"phi-max unknown to the row", "trace gen:fbm:32x32 -t cone --phi-max -45 --rays {tmp}/rays.csv", 1, "", "technique 'cone' has no phi-max parameter"},
    {"bake exterior", "bake gen:fbm:24x24 --maps safety-sd,cone --visibility exterior -o {tmp}/ext.exr --deterministic", 0, "safety-sd: 1 arrays", ""},
    {"trace exterior maps", "trace gen:fbm:24x24 -t safety-sd --visibility exterior --maps {tmp}/ext.exr --rays {tmp}/rays.csv", 0, "hit,t", ""},
    {"visibility unknown to every row", "bake gen:fbm:24x24 --maps cone,maxmip --visibility exterior -o {tmp}/x.exr", 1, "", "none of cone, maxmip has a visibility parameter"},
    {"bad visibility", "trace gen:fbm:24x24 -t safety-sd --visibility some --rays {tmp}/rays.csv", 1, "", "relief: error:"},
    {"bake param no row has", "bake gen:fbm:24x24 --maps cone,maxmip --param warp=1 -o {tmp}/x.exr", 1, "", "none of cone, maxmip has this parameter"},
    // -t all draws what can honour the options and names the rest; a named row is refused.
    {"all skips what cannot shadow", "render gen:peaks6:24x24 -t all --shadows --size 16x16 --out-dir {tmp}/allsh --deterministic", 0, "| safety-cc | exact |", "skipping curves: --shadows"},
    {"all skips what cannot tile", "render gen:peaks6:24x24 -t all --edge repeat --size 16x16 --out-dir {tmp}/allrep --deterministic", 0, "| exact | exact |", "skipping curves: --edge repeat"},
    {"max-steps without a cap", "trace gen:fbm:24x24 -t parallax --max-steps 3 --rays {tmp}/rays.csv", 1, "", "technique 'parallax' has no iteration cap parameter"},
};

TEST_F(Cli, RoleOptions) {
    for (const CliCase& c : kRoleCases) run(c);
}

// A source's window (SOURCE@crop=X,Y,W,H) is a source like any other in every command.
const CliCase kCropCases[] = {
    {"crop info", "info gen:fbm:40x30@crop=2,3,16,8", 0, "16x8 samples", ""},
    {"crop info renormalized", "info gen:fbm:40x30@crop=2,3,16,8 --format json", 0, "\"max\": 1.0", ""},
    {"crop real map", "info {src}/data/earth-topology-2048x1024.png@crop=900,0,64,32", 0, "64x32 samples", ""},
    {"crop trace", "trace gen:peaks6:48x48@crop=8,8,32,32 --rays {tmp}/rays.csv", 0, "hit,t", ""},
    {"crop render", "render gen:peaks6:48x48@crop=8,8,32,32 --size 32x24 -o {tmp}/crop.png --deterministic", 0, "| exact | exact |", ""},
    {"crop bake", "bake gen:fbm:48x48@crop=4,4,24,24 --maps cone -o {tmp}/crop.exr --deterministic", 0, "wrote", ""},
    {"crop baked maps", "trace gen:fbm:48x48@crop=4,4,24,24 -t cone --maps {tmp}/crop.exr --rays {tmp}/rays.csv", 0, "hit,t", ""},
    {"crop other window stale", "trace gen:fbm:48x48@crop=5,4,24,24 -t cone --maps {tmp}/crop.exr --rays {tmp}/rays.csv", 3, "", "stale maps"},
    {"crop bench", "bench --preset quick --heightfields gen:fbm:48x48:1@crop=4,4,32,32,gen:walls:40x40 -t exact --smoke --no-images --out-dir {tmp}/bcrop --deterministic", 0, "results.csv", ""},
    {"centre crop info", "info gen:fbm:40x30@centre=38,2,16,8", 0, "16x8 samples", ""},
    {"centre crop too large", "info gen:fbm:40x30@centre=20,15,41,8", 3, "", "crop 41x8 around (20, 15) is not inside the 40x30 map"},
    {"crop outside", "info gen:fbm:40x30@crop=30,0,16,8", 3, "", "crop 16x8 at (30, 0) is not inside the 40x30 map"},
    {"crop negative corner", "info gen:fbm:40x30@crop=-1,0,16,8", 3, "", "not inside"},
    {"crop empty", "info gen:fbm:40x30@crop=0,0,0,8", 3, "", "not inside"},
    {"crop too few numbers", "info gen:fbm:40x30@crop=1,2,3", 1, "", "FILE@crop=X,Y,W,H"},
    {"crop not a number", "info gen:fbm:40x30@crop=1,2,w,4", 1, "", "FILE@crop=X,Y,W,H"},
    {"crop of a missing file", "info {tmp}/does-not-exist.png@crop=0,0,4,4", 2, "", "does-not-exist.png"},
};

TEST_F(Cli, CropSources) {
    for (const CliCase& c : kCropCases) run(c);
}

TEST_F(Cli, FailedRenderLeavesNoPartialOutput) {
    // An unreadable colour map fails after the render; nothing may be left in the folder.
    const fs::path dir = tmp / "atomic";
    fs::create_directories(dir);
    run({"bad colour map", "render gen:flat:8x8 --size 8x8 --color {tmp}/garbage.png -o {tmp}/atomic/x.png", 3, "", "garbage.png"});
    EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
