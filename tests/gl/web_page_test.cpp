// The web preview (web/, `relief serve`): the page's technique table against the registry, the
// server's refusals (a path outside its roots, a port in use), and the page in headless Chromium
// (as tests/bench_test.cpp runs it) on a baked PNG and a baked KTX2 map: no console message, and
// its screenshot against `relief render --mesh` of the same view.
//
// Threshold (the shading may differ by float rounding, mip filtering of the normal map made in
// JavaScript and SwiftShader vs llvmpipe; the covered area must agree): at most 0.5 % of the
// pixels covered in one image and not the other, at most 3 % of the pixels off by more than 8 of
// 255 in some channel and at most 1 % off by more than 32. Measured when written: 0.01 %,
// 0.03 % and 0.02 % (cube, cone PNG, self-shadows), 0.01 %, 2.1 % and 0.02 % (sphere, maxmip
// KTX2).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/registry.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

namespace relief {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path freshDir(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / fmt::format("relief_web_{}_{}", name, ::getpid());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

int testPort(int offset) { return 20000 + int(::getpid() % 20000) + offset; }

// `relief serve` in the background for the life of this object.
struct Server {
    Server(int port, const fs::path& data, const fs::path& dir) : port(port) {
        const std::string command = fmt::format(
            "{} serve --port {} --data {} > {} 2>&1 & echo $! > {}", RELIEF_CLI_PATH, port,
            data.string(), (dir / "serve.log").string(), (dir / "serve.pid").string());
        EXPECT_EQ(std::system(command.c_str()), 0);
        pid = std::stoi(readText(dir / "serve.pid"));
        httplib::Client client("127.0.0.1", port);
        for (int k = 0; k < 100 && !client.Get("/"); ++k)
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ~Server() { std::system(fmt::format("kill {}", pid).c_str()); }
    int port, pid = 0;
};

TEST(WebPage, TechniqueTableMatchesTheRegistry) {
    const std::string table = readText(fs::path(RELIEF_SOURCE_DIR) / "web" / "techniques.js");
    const std::regex row(
        R"('([a-z-]+)': \{file: '([a-z_]+\.glsl)', fn: '(\w+)', samplers: \[(.*)\], maxSteps: (\d+), binarySteps: (\d+)\})");
    int rows = 0;
    for (auto it = std::sregex_iterator(table.begin(), table.end(), row);
         it != std::sregex_iterator(); ++it, ++rows) {
        const std::smatch& m = *it;
        auto info = lookupTechnique(m[1].str());
        ASSERT_TRUE(info) << m[1];
        const TechniqueInfo& t = **info;
        EXPECT_EQ(m[2].str(), t.shaderFile) << t.name;
        EXPECT_EQ(m[3].str(), t.shaderFunction) << t.name;
        std::string samplers;
        for (const ShaderSampler& s : t.shaderSamplers)
            samplers += fmt::format("{}['{}', '{}'{}]", samplers.empty() ? "" : ", ", s.name,
                                    s.array, s.mipChain ? ", true" : "");
        EXPECT_EQ(m[4].str(), samplers) << t.name;
        const ParamSpec* cap = paramWithRole(t, ParamRole::IterationCap);
        EXPECT_EQ(std::stod(m[5].str()), cap ? cap->defaultValue : 0.0) << t.name;
        double binary = 0.0;
        for (const ParamSpec& p : t.params)
            if (p.name == "binary-steps") binary = p.defaultValue;
        EXPECT_EQ(std::stod(m[6].str()), binary) << t.name;
    }
    EXPECT_GE(rows, 8);
}

TEST(WebPage, ServerRefusesPathsOutsideItsRootsAndATakenPort) {
    const fs::path dir = freshDir("serve");
    std::ofstream(dir / "inside.txt") << "inside\n";
    Server server(testPort(0), dir, dir);
    httplib::Client client("127.0.0.1", server.port);
    auto ok = client.Get("/data/inside.txt");
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200);
    EXPECT_EQ(client.Get("/")->status, 200);
    EXPECT_EQ(client.Get("/shaders/relief/common.glsl")->status, 200);
    EXPECT_EQ(client.Get("/gl/preview_fragment.glsl")->status, 200);
    for (const char* outside : {"/../CMakeLists.txt", "/shaders/relief/../../CMakeLists.txt",
                                "/data/../serve.log/../../etc/passwd", "/%2e%2e/CMakeLists.txt",
                                "/gl/mesh_fragment.glsl", "/data/"})
        EXPECT_EQ(client.Get(outside)->status, 404) << outside;
    const std::string second = fmt::format("{} serve --port {} > {} 2>&1", RELIEF_CLI_PATH,
                                           server.port, (dir / "second.log").string());
    EXPECT_EQ(WEXITSTATUS(std::system(second.c_str())), 2);
    EXPECT_NE(readText(dir / "second.log").find("cannot listen on 127.0.0.1"), std::string::npos)
        << readText(dir / "second.log");
}

struct Compared {
    double coverageMismatch = 0, over8 = 0, over32 = 0;
};

Compared compare(const ImageRgb8& a, const ImageRgb8& b) {
    const Rgb8 background(26, 28, 33);  // 0.10, 0.11, 0.13 in 8 bits
    auto covered = [&](const Rgb8& p) {
        return std::abs(int(p.x) - background.x) > 3 || std::abs(int(p.y) - background.y) > 3 ||
               std::abs(int(p.z) - background.z) > 3;
    };
    Compared c;
    for (size_t k = 0; k < a.pixels.size(); ++k) {
        const Rgb8 p = a.pixels[k], q = b.pixels[k];
        const int d = std::max({std::abs(int(p.x) - int(q.x)), std::abs(int(p.y) - int(q.y)),
                                std::abs(int(p.z) - int(q.z))});
        c.coverageMismatch += covered(p) != covered(q);
        c.over8 += d > 8;
        c.over32 += d > 32;
    }
    const double n = double(a.pixels.size());
    return {c.coverageMismatch / n, c.over8 / n, c.over32 / n};
}

TEST(WebPage, HeadlessChromiumMatchesRenderMesh) {
    ASSERT_EQ(std::system("command -v chromium > /dev/null"), 0)
        << "chromium is missing: run scripts/install-deps.sh";
    const fs::path dir = freshDir("page");
    const fs::path height = fs::path(RELIEF_SOURCE_DIR) / "data" / "colorado-elevation-400.png";
    fs::copy_file(height, dir / "height.png");
    const std::string cli = RELIEF_CLI_PATH;
    auto run = [&](const std::string& args) {
        const std::string command = cli + " " + args + " > " + (dir / "cli.log").string() + " 2>&1";
        ASSERT_EQ(std::system(command.c_str()), 0) << command << "\n" << readText(dir / "cli.log");
    };
    run(fmt::format("bake {} -t cone --param bits=16 -o {}", (dir / "height.png").string(),
                    (dir / "cone.png").string()));
    run(fmt::format("bake {} -t maxmip -o {}", (dir / "height.png").string(),
                    (dir / "maxmip.ktx2").string()));
    Server server(testPort(1), dir, dir);
    struct Case {
        const char *mesh, *technique, *map, *params, *page;  // page: its query for the same
    } cases[] = {{"cube", "cone", "cone.png", "--param bits=16 --shadows", "&shadows=1"},
                 {"sphere", "maxmip", "maxmip.ktx2", "", ""}};
    {  // the page as a new user opens it: a prompt to load files, no console message
        const std::string chromium = fmt::format(
            "timeout 120 chromium --headless --no-sandbox --enable-unsafe-swiftshader "
            "--use-angle=swiftshader --enable-logging=stderr --v=0 --virtual-time-budget=5000 "
            "--user-data-dir={} --dump-dom http://127.0.0.1:{}/ > {} 2> {}",
            (dir / "profile_empty").string(), server.port, (dir / "empty.html").string(),
            (dir / "empty.log").string());
        ASSERT_EQ(std::system(chromium.c_str()), 0);
        EXPECT_NE(readText(dir / "empty.html").find("load a heightmap PNG"), std::string::npos)
            << readText(dir / "empty.html");
        EXPECT_EQ(readText(dir / "empty.log").find("CONSOLE"), std::string::npos)
            << readText(dir / "empty.log");
    }
    for (const Case& c : cases) {
        const std::string name = fmt::format("{}_{}", c.mesh, c.technique);
        const std::string url = fmt::format(
            "'http://127.0.0.1:{}/?ui=0&size=400x300&mesh={}&technique={}&height=/data/"
            "height.png&map=/data/{}&elevation=35&azimuth=50{}'",
            server.port, c.mesh, c.technique, c.map, c.page);
        const std::string chromium = fmt::format(
            "timeout 120 chromium --headless --no-sandbox --enable-unsafe-swiftshader "
            "--use-angle=swiftshader --enable-logging=stderr --v=0 --virtual-time-budget=20000 "
            "--window-size=400,300 --user-data-dir={}",
            (dir / ("profile_" + name)).string());
        const fs::path dom = dir / (name + ".html"), console = dir / (name + ".log");
        ASSERT_EQ(std::system(fmt::format("{} --dump-dom {} > {} 2> {}", chromium, url,
                                          dom.string(), console.string())
                                  .c_str()),
                  0);
        const std::string page = readText(dom);
        EXPECT_NE(page.find("data-state=\"ready\""), std::string::npos) << name << "\n" << page;
        EXPECT_EQ(readText(console).find("CONSOLE"), std::string::npos) << readText(console);
        const fs::path shot = dir / (name + "_page.png"), reference = dir / (name + "_ref.png");
        ASSERT_EQ(std::system(fmt::format("{} --screenshot={} {} > /dev/null 2>&1", chromium,
                                          shot.string(), url)
                                  .c_str()),
                  0);
        run(
            fmt::format("render {} -t {} {} --maps {} --mesh {} --size 400x300 --elevation 35 "
                        "--azimuth 50 -o {}",
                        (dir / "height.png").string(), c.technique, c.params,
                        (dir / c.map).string(), c.mesh, reference.string()));
        auto a = loadColorImage(shot.string());
        auto b = loadColorImage(reference.string());
        ASSERT_TRUE(a && b) << name;
        ASSERT_EQ(a->width, b->width);
        ASSERT_EQ(a->height, b->height);
        const Compared d = compare(*a, *b);
        EXPECT_LE(d.coverageMismatch, 0.005) << name;
        EXPECT_LE(d.over8, 0.03) << name;
        EXPECT_LE(d.over32, 0.01) << name;
        std::cout << fmt::format("{}: coverage mismatch {:.3f} %, > 8: {:.2f} %, > 32: {:.2f} %\n",
                                 name, 100 * d.coverageMismatch, 100 * d.over8, 100 * d.over32);
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace relief
