// relief view, run as a user would under Xvfb: a few frames, then the screenshot must exist, have
// the window's size and show a relief (many colours, mostly not the background); with --mesh
// every built-in mesh is covered, the A/B split shows A's left half and B's right half, and the
// panel stays in the window's left third. It needs xvfb-run (scripts/install-deps.sh installs
// it) or a display, and skips only without both.
#include <gtest/gtest.h>
#include <relief/io/heightfield_io.h>
#include <relief/preview/mesh.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
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

    // The prefix that gives relief a display, or empty when there is none (the test skips).
    static std::optional<std::string> displayPrefix() {
        if (onPath("xvfb-run")) return "xvfb-run -a";
        if (std::getenv("DISPLAY")) return "";
        return std::nullopt;
    }

    // `relief view ARGS --frames 2 --size WxH --screenshot NAME.png`, the screenshot read back.
    ImageRgb8 screenshot(const std::string& prefix, const std::string& name,
                         const std::string& args, ivec2 size) const {
        const fs::path png = m_dir / (name + ".png"), log = m_dir / (name + ".log");
        const std::string command = "view " + args + " --frames 2 --size " +
                                    std::to_string(size.x) + "x" + std::to_string(size.y) +
                                    " --screenshot " + png.string();
        const int code = run(prefix, command, log);
        EXPECT_EQ(code, 0) << "relief " << command << "\n" << readFile(log);
        auto image = loadColorImage(png.string());
        EXPECT_TRUE(image) << (image ? "" : image.error().message);
        if (!image) return ImageRgb8(size.x, size.y);
        EXPECT_EQ(image->width, size.x);
        EXPECT_EQ(image->height, size.y);
        return std::move(*image);
    }

    fs::path m_dir;
};

// Pixels of columns [x0, x1) that differ between a and b (same size).
size_t differingPixels(const ImageRgb8& a, const ImageRgb8& b, int x0, int x1) {
    size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = x0; x < x1; ++x) n += a.at(x, y) != b.at(x, y);
    return n;
}

#define RELIEF_NEED_DISPLAY(prefix)                            \
    const std::optional<std::string> prefix = displayPrefix(); \
    if (!prefix)                                               \
    GTEST_SKIP() << "neither xvfb-run nor a DISPLAY (scripts/install-deps.sh installs xvfb)"

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

TEST_F(Viewer, EachBuiltinMeshIsCovered) {
    RELIEF_NEED_DISPLAY(prefix);
    constexpr double kMinMeshFraction = 0.05;  // of the window, not the background colour
    for (std::string_view mesh : preview::kBuiltinMeshes) {
        SCOPED_TRACE(mesh);
        const std::string name(mesh);
        const ImageRgb8 image =
            screenshot(*prefix, name, "gen:peaks6:64x64 -t cone --shadows --tiles 2 --mesh " + name,
                       ivec2(240, 180));
        const Rgb8 background = image.at(0, 0);
        size_t covered = 0;
        std::set<uint32_t> colours;
        for (const Rgb8& p : image.pixels) {
            covered += p != background;
            colours.insert(uint32_t(p.x) << 16 | uint32_t(p.y) << 8 | p.z);
        }
        EXPECT_GE(double(covered) / double(image.pixels.size()), kMinMeshFraction);
        EXPECT_GE(colours.size(), kMinDistinctColours);
    }
}

// The viewer draws what relief render --mesh writes for the same options.
TEST_F(Viewer, AMeshLooksAsRenderMeshDrawsIt) {
    RELIEF_NEED_DISPLAY(prefix);
    const ivec2 size(200, 150);
    const std::string common = "gen:peaks6:64x64 --mesh cylinder -t relaxed-cone --shadows";
    const ImageRgb8 viewed = screenshot(*prefix, "viewed", common, size);
    const fs::path rendered = m_dir / "rendered.png", log = m_dir / "rendered.log";
    ASSERT_EQ(run("", "render " + common + " --size 200x150 -o " + rendered.string(), log), 0)
        << readFile(log);
    auto image = loadColorImage(rendered.string());
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(differingPixels(viewed, *image, 0, size.x), 0u);
}

// A on the left, B on the right: the split's halves are those of A alone and of B alone (but for
// the line between them), and A and B differ there, so the split shows two techniques.
TEST_F(Viewer, SplitShowsATheLeftAndBTheRight) {
    RELIEF_NEED_DISPLAY(prefix);
    const ivec2 size(240, 180);
    const std::string common = "gen:peaks6:64x64 --mesh sphere --depth-ratio 0.3 --elevation 10 ";
    const ImageRgb8 a = screenshot(*prefix, "a", common + "-t cone", size);
    const ImageRgb8 b = screenshot(*prefix, "b", common + "-t parallax", size);
    const ImageRgb8 split = screenshot(*prefix, "split", common + "-t cone --split parallax", size);
    constexpr int kLine = 2;  // the split line's half-width, and a pixel of margin
    const int half = size.x / 2;
    EXPECT_EQ(differingPixels(split, a, 0, half - kLine), 0u);
    EXPECT_EQ(differingPixels(split, b, half + kLine, size.x), 0u);
    EXPECT_GT(differingPixels(a, b, half + kLine, size.x), 0u) << "cone and parallax look alike";
    EXPECT_GT(differingPixels(split, a, half + kLine, size.x), 0u);
}

// The panel: the columns where a screenshot with it differs from one without lie in the left
// third of a 1024x768 window, on the block and on a mesh (and it is there at all).
TEST_F(Viewer, PanelTakesAtMostAThirdOfTheWidth) {
    RELIEF_NEED_DISPLAY(prefix);
    const ivec2 size(1024, 768);
    for (const std::string args :
         {"gen:peaks6:64x64", "gen:peaks6:64x64 --mesh cube --split linear"}) {
        SCOPED_TRACE(args);
        const ImageRgb8 without = screenshot(*prefix, "without", args, size);
        const ImageRgb8 with = screenshot(*prefix, "with", args + " --screenshot-panel", size);
        const int third = size.x / 3;
        EXPECT_GT(differingPixels(with, without, 0, third), 0u) << "no panel in the screenshot";
        EXPECT_EQ(differingPixels(with, without, third, size.x), 0u);
    }
}

// Folded, the panel is its title bar: nothing of it below the window's top rows.
TEST_F(Viewer, AFoldedPanelIsItsTitleBar) {
    RELIEF_NEED_DISPLAY(prefix);
    const ivec2 size(480, 360);
    constexpr int kMaxTitleRows = 40;
    const std::string args = "gen:peaks6:64x64 --mesh plane --fold-panel";
    const ImageRgb8 without = screenshot(*prefix, "without", args, size);
    const ImageRgb8 with = screenshot(*prefix, "with", args + " --screenshot-panel", size);
    size_t below = 0, title = 0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
            (y < kMaxTitleRows ? title : below) += with.at(x, y) != without.at(x, y);
    EXPECT_GT(title, 0u);
    EXPECT_EQ(below, 0u);
}

TEST_F(Viewer, BadMeshesAreRefusedBeforeAWindowOpens) {
    const fs::path log = m_dir / "mesh.log";
    const auto code = [&](const std::string& args) {
        return run("env -u DISPLAY", "view gen:peaks6:16x16 " + args, log);
    };
    EXPECT_EQ(code("--mesh teapot"), 1) << readFile(log);
    EXPECT_NE(readFile(log).find("teapot"), std::string::npos) << readFile(log);
    EXPECT_EQ(code("--mesh " + (m_dir / "missing.gltf").string()), 2) << readFile(log);
    { std::ofstream(m_dir / "bad.gltf") << "{ not json"; }
    EXPECT_EQ(code("--mesh " + (m_dir / "bad.gltf").string()), 3) << readFile(log);
    EXPECT_EQ(code("--mesh plane -t exact"), 5) << readFile(log);
    EXPECT_NE(readFile(log).find("no shader-library function"), std::string::npos) << readFile(log);
    EXPECT_EQ(code("--mesh plane --split nope"), 1) << readFile(log);
    EXPECT_EQ(code("--split cone"), 1) << readFile(log);  // --split without --mesh
    EXPECT_NE(readFile(log).find("--split: read with --mesh only"), std::string::npos)
        << readFile(log);
    EXPECT_EQ(code("--mesh plane --overlay steps"), 1) << readFile(log);
    EXPECT_EQ(code("--screenshot-panel"), 1) << readFile(log);  // without --screenshot
    EXPECT_FALSE(fs::exists(m_dir / "relief-view-001.png"));
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
