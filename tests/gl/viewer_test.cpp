// relief view, run as a user would under Xvfb: a few frames, then the screenshot must exist, have
// the window's size and show a relief (many colours, mostly not the background). It needs
// xvfb-run (scripts/install-deps.sh installs it) or a display, and skips only without both.
#include <gtest/gtest.h>
#include <relief/io/heightfield_io.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace relief {
namespace {

namespace fs = std::filesystem;

struct ViewCase {
    const char* name;
    int width, height;
    std::string args;  // after "relief view gen:peaks6:64x64 --frames 2"
};

const ViewCase kCases[] = {
    {"exact-shading", 320, 240, ""},
    {"cone-steps", 256, 200, "-t cone --overlay steps"},
    {"linear-error", 300, 220, "-t linear --param max-steps=8 --overlay error"},
    {"relaxed-cone-shadows", 280, 210, "-t relaxed-cone --shadows --elevation 20"},
};

// Pixels that differ from the corner (background at the default distance), distinct colours.
constexpr double kMinReliefFraction = 0.1;
constexpr size_t kMinDistinctColours = 16;

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// An executable of that name in a folder of PATH (no shell: nothing is written anywhere).
bool onPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    for (std::string_view rest = path ? path : ""; !rest.empty();) {
        const size_t colon = rest.find(':');
        const std::string dir(rest.substr(0, colon));
        rest = colon == std::string_view::npos ? std::string_view{} : rest.substr(colon + 1);
        if (!dir.empty() && ::access((dir + "/" + program).c_str(), X_OK) == 0) return true;
    }
    return false;
}

int exitCode(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

class Viewer : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("relief_viewer_test_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    // Runs `prefix relief ARGS` in the test folder; stdout and stderr go to `log`.
    int run(const std::string& prefix, const std::string& args, const fs::path& log) const {
        const std::string command = "cd '" + m_dir.string() + "' && " + prefix + " " +
                                    RELIEF_CLI_PATH + " " + args + " >'" + log.string() + "' 2>&1";
        return exitCode(std::system(command.c_str()));
    }

    fs::path m_dir;
};

TEST_F(Viewer, ScreenshotsShowTheRelief) {
    std::string prefix;
    if (onPath("xvfb-run"))
        prefix = "xvfb-run -a";
    else if (!std::getenv("DISPLAY"))
        GTEST_SKIP() << "neither xvfb-run nor a DISPLAY (scripts/install-deps.sh installs xvfb)";
    for (const ViewCase& c : kCases) {
        SCOPED_TRACE(c.name);
        const fs::path png = m_dir / (std::string(c.name) + ".png");
        const fs::path log = m_dir / (std::string(c.name) + ".log");
        const std::string args = "view gen:peaks6:64x64 --frames 2 --size " +
                                 std::to_string(c.width) + "x" + std::to_string(c.height) +
                                 " --screenshot " + png.string() + " " + c.args;
        ASSERT_EQ(run(prefix, args, log), 0) << "relief " << args << "\n" << readFile(log);
        auto image = loadColorImage(png.string());
        ASSERT_TRUE(image) << image.error().message;
        ASSERT_EQ(image->width, c.width);
        ASSERT_EQ(image->height, c.height);
        const Rgb8 background = image->at(0, 0);
        size_t relief = 0;
        std::set<uint32_t> colours;
        for (const Rgb8& p : image->pixels) {
            relief += p != background;
            colours.insert(uint32_t(p.x) << 16 | uint32_t(p.y) << 8 | p.z);
        }
        EXPECT_GE(double(relief) / double(image->pixels.size()), kMinReliefFraction);
        EXPECT_GE(colours.size(), kMinDistinctColours);
    }
}

TEST_F(Viewer, WithoutADisplayTheErrorSaysWhatWasTried) {
    const fs::path log = m_dir / "no-display.log";
    const int code =
        run("env -u DISPLAY -u WAYLAND_DISPLAY", "view gen:peaks6:16x16 --frames 1", log);
    const std::string text = readFile(log);
    EXPECT_EQ(code, 5) << text;  // unsupported: no display at all
    EXPECT_NE(text.find("relief: error: relief view needs a display"), std::string::npos) << text;
    EXPECT_NE(text.find("DISPLAY unset"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(m_dir / "relief-view-001.png"));
}

TEST_F(Viewer, HelpListsTheCommand) {
    const fs::path log = m_dir / "help.log";
    ASSERT_EQ(run("", "help", log), 0) << readFile(log);
    EXPECT_NE(readFile(log).find("  view "), std::string::npos) << readFile(log);
}

TEST_F(Viewer, UnknownAndCpuOnlyTechniquesAreRefusedBeforeAWindowOpens) {
    const fs::path log = m_dir / "technique.log";
    EXPECT_EQ(run("env -u DISPLAY", "view gen:peaks6:16x16 -t nope", log), 1) << readFile(log);
    EXPECT_NE(readFile(log).find("the viewer shows: exact"), std::string::npos) << readFile(log);
    EXPECT_EQ(run("env -u DISPLAY", "view gen:peaks6:16x16 -t curves", log), 5) << readFile(log);
    EXPECT_NE(readFile(log).find("no GLSL tracer"), std::string::npos) << readFile(log);
}

}  // namespace
}  // namespace relief
