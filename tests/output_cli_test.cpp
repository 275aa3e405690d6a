// Hostile outputs, as data: what is at the path before (a shell setup in the case's own folder),
// the command, the exit code and stderr, and a shell check of what is there after. Full disks
// are covered by tests/output_test.cpp's injected failure: no case writes to a system device.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct OutputCase {
    const char* name;
    const char* setup;    // shell, in the case's folder
    const char* command;  // bash; `relief` is the binary; stdout goes to out.txt unless redirected
    int exitCode;
    const char* stderrFragment;
    const char* check;    // shell that must succeed afterwards
};

// A 32x32 surface, a small image; big.csv gives more hit text than a pipe holds.
#define G "gen:peaks6:32x32 --size 40x30 --deterministic"
#define NO_TEMP "! ls -A | grep -q relief-tmp"

const OutputCase kOutputCases[] = {
    {"file replaced, mode kept", "echo old > a.png; chmod 640 a.png", "relief render " G " -o a.png", 0, "",
     "[ $(stat -c %a a.png) = 640 ] && head -c4 a.png | grep -q PNG && " NO_TEMP},
    {"bake keeps mode 600", "echo old > m.exr; chmod 600 m.exr", "relief bake gen:peaks6:32x32 --maps cone -o m.exr", 0, "",
     "[ $(stat -c %a m.exr) = 600 ] && [ $(wc -c < m.exr) -gt 100 ]"},
    {"symlink target written", "echo old > t.png; ln -s t.png l.png", "relief render " G " -o l.png", 0, "",
     "[ -L l.png ] && head -c4 t.png | grep -q PNG"},
    {"dangling symlink makes its target", "ln -s new.png l.png", "relief render " G " -o l.png", 0, "",
     "[ -L l.png ] && [ -f new.png ]"},
    {"fifo streamed", "mkfifo f.png", "cat f.png > got.png & relief render " G " -o f.png; s=$?; wait; exit $s", 0, "",
     "[ -p f.png ] && head -c4 got.png | grep -q PNG"},
    {"trace to a fifo", "mkfifo f.csv", "cat f.csv > got.csv & relief trace gen:peaks6:32x32 --rays big.csv -o f.csv; s=$?; wait; exit $s", 0, "",
     "[ -p f.csv ] && [ $(wc -l < got.csv) = 20001 ]"},
    {"directory refused", "mkdir d.png", "relief render " G " -o d.png", 2, "d.png: is a directory", "[ -d d.png ]"},
    {"bake into a directory refused", "mkdir d.exr", "relief bake gen:peaks6:32x32 --maps cone -o d.exr", 2, "d.exr: is a directory", "[ -d d.exr ]"},
    {"socket refused", "python3 -c \"import socket; socket.socket(socket.AF_UNIX).bind('s.png')\"",
     "relief render " G " -o s.png", 2, "s.png: is a socket", "[ -S s.png ]"},
    {"missing folder", "", "relief render " G " -o no/such/a.png", 2, "no/such/a.png: folder 'no/such' does not exist", "[ ! -e no ]"},
    {"transaction: missing depth folder", "echo keep > a.png", "relief render " G " -o a.png --depth-out missing/dir/d.exr", 2,
     "missing/dir/d.exr: folder 'missing/dir' does not exist", "[ \"$(cat a.png)\" = keep ] && " NO_TEMP},
    {"transaction: steps into a directory", "echo keep > a.png; echo keep > d.exr; mkdir s.png",
     "relief render " G " -o a.png --depth-out d.exr --steps-out s.png", 2, "s.png: is a directory",
     "[ \"$(cat a.png)\" = keep ] && [ \"$(cat d.exr)\" = keep ] && " NO_TEMP},
    {"transaction: out-dir all or nothing", "mkdir out; echo keep > out/exact.png; mkdir out/summary.md",
     "relief render " G " -t exact,cone --out-dir out", 2, "summary.md: is a directory",
     "[ \"$(cat out/exact.png)\" = keep ] && [ ! -e out/cone.png ]"},
    {"one file for two outputs", "", "relief render " G " -o x.png --depth-out x.png", 1, "x.png: given for two outputs",
     "[ ! -e x.png ]"},
    {"image on stdout, summary on stderr", "", "relief render " G " -o - > img.png", 0, "| exact | exact |",
     "head -c4 img.png | grep -q PNG"},
    {"trace to stdout", "", "relief trace gen:peaks6:32x32 --rays big.csv -o - > hits.csv", 0, "",
     "[ $(wc -l < hits.csv) = 20001 ]"},
    // Rays streamed in on stdin (a pipe, read as it comes, with --max-rays), hits streamed out.
    {"rays from a pipe, hits to a pipe", "",
     "cat big.csv | relief trace gen:peaks6:32x32 --rays - -o - | cat > piped.csv && relief trace gen:peaks6:32x32 --rays big.csv -o file.csv",
     0, "", "cmp piped.csv file.csv && [ $(wc -l < piped.csv) = 20001 ]"},
    {"rays from a slow pipe", "",
     "(head -n 7000 big.csv; sleep 0.3; tail -n +7001 big.csv) | relief trace gen:peaks6:32x32 --rays - -o - > slow.csv", 0, "",
     "cmp slow.csv <(relief trace gen:peaks6:32x32 --rays big.csv)"},
    {"--max-rays on a pipe", "", "cat big.csv | relief trace gen:peaks6:32x32 --rays - --max-rays 100 -o h.csv", 3,
     "stdin:102: more than 100 rays (--max-rays)", "[ ! -e h.csv ] && " NO_TEMP},
    {"a pipe by name: use -", "", "cat big.csv | relief trace gen:peaks6:32x32 --rays /dev/stdin", 2,
     "is a FIFO (pipe), not a ray file (pipe rays in with --rays -)", "true"},
    {"npy on stdin is not CSV", "relief rays gen:peaks6:32x32 --size 4x4 -o r.npy",
     "relief trace gen:peaks6:32x32 --rays - < r.npy", 3, "stdin:1: NUL byte", "true"},
    {"rays to a pipe, large", "", "relief rays gen:peaks6:32x32 --size 400x300 | cat > r.csv", 0, "",
     "[ $(wc -l < r.csv) = 120001 ] && head -1 r.csv | grep -qx ox,oy,oz,dx,dy,dz"},
    {"npy rays in, npy hits out", "relief rays gen:peaks6:32x32 --size 200x150 -o r.npy",
     "relief trace gen:peaks6:32x32 --rays r.npy -o h.npy && relief trace gen:peaks6:32x32 --rays r.npy | cat > h.csv", 0, "",
     "[ $(wc -l < h.csv) = 30001 ] && [ $(stat -c %s h.npy) -gt 750000 ] && head -c6 h.npy | grep -q NUMPY && " NO_TEMP},
    {"stdout reader closes early", "", "relief trace gen:peaks6:32x32 --rays big.csv -o - | true; exit ${PIPESTATUS[0]}", 2,
     "stdout: write failed: Broken pipe", "true"},
    {"fifo reader closes early", "mkfifo f.csv", "(exec 3<f.csv) & relief trace gen:peaks6:32x32 --rays big.csv -o f.csv; s=$?; wait; exit $s", 2,
     "f.csv: write failed: Broken pipe", "[ -p f.csv ]"},
    {"info to a closed stdout", "", "relief info gen:fbm:40x30 >&-", 2, "stdout: write failed", "true"},
    {"trace to a closed stdout", "", "relief trace gen:peaks6:32x32 --rays big.csv -o - >&-", 2, "stdout: write failed", NO_TEMP},
    {"help to a closed stdout", "", "relief help >&-", 2, "stdout: write failed", "true"},
    {"longest valid name", "", "relief render " G " -o $(printf 'n%.0s' $(seq 251)).png", 0, "",
     "[ -f $(printf 'n%.0s' $(seq 251)).png ] && " NO_TEMP},
    {"stale temp removed", "echo x > .relief-tmp-0123456789abcdef; echo x > .relief-tmp-other",
     "relief render " G " -o a.png", 0, "", "[ ! -e .relief-tmp-0123456789abcdef ] && [ -e .relief-tmp-other ]"},
};

#undef G
#undef NO_TEMP

class OutputCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        root = fs::temp_directory_path() / ("relief_output_cli_" + std::to_string(::getpid()));
        fs::remove_all(root);
        fs::create_directories(root);
        std::ofstream rays(root / "big.csv");
        rays << "ox,oy,oz,dx,dy,dz\n";
        for (int k = 0; k < 20000; ++k) rays << (k % 30) + 1 << ",5,30,0.1,0.2,-1\n";
    }
    static void TearDownTestSuite() { fs::remove_all(root); }

    static std::string slurp(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }

    static void check(const OutputCase& c, int index) {
        const fs::path dir = root / ("case" + std::to_string(index));
        fs::create_directories(dir);
        fs::copy_file(root / "big.csv", dir / "big.csv");
        std::ofstream(dir / "case.sh")
            << "cd '" << dir.string() << "' || exit 99\n"
            << "relief() { '" << RELIEF_CLI_PATH << "' \"$@\"; }\n"
            << c.setup << "\n"
            << "(" << c.command << ") >out.txt 2>err.txt\n"
            << "echo $? > rc.txt\n"
            << "(" << c.check << ") && echo ok > check.txt\n";
        // A bound, so a regression that blocks (a FIFO replaced, its reader waiting) fails, not hangs.
        (void)std::system(("timeout -k 5 60 bash '" + (dir / "case.sh").string() + "'").c_str());
        const std::string rc = slurp(dir / "rc.txt"), err = slurp(dir / "err.txt");
        EXPECT_EQ(std::atoi(rc.c_str()), c.exitCode) << c.name << "\nstderr: " << err;
        EXPECT_NE(err.find(c.stderrFragment), std::string::npos)
            << c.name << ": stderr lacks '" << c.stderrFragment << "':\n" << err;
        EXPECT_TRUE(fs::exists(dir / "check.txt")) << c.name << ": check failed: " << c.check;
    }
    static inline fs::path root;
};

TEST_F(OutputCli, Table) {
    int index = 0;
    for (const OutputCase& c : kOutputCases) check(c, index++);
}

}  // namespace
