// `relief bench --preset quick` on tiny inputs: the outputs exist and parse, and the numbers are
// sane (exact and the exact-contract techniques have zero error, Embree agrees with exact); the
// HTML report renders in headless Chromium with every image loaded and no console error.
#include <relief/io/heightfield_io.h>

#include <fmt/format.h>
#include <relief/core/isa.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace {

namespace fs = std::filesystem;

TEST(BenchCommand, QuickPresetWritesSaneReport) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_test_" + std::to_string(::getpid()));
    const std::string command = std::string(RELIEF_CLI_PATH) + " bench --preset quick --threads 2 --out-dir " +
                                out.string() + " > " + (out.string() + ".log") + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    for (const char* name : {"results.csv", "results.json", "index.html", "error_vs_cap.svg", "steps_vs_elevation.svg"})
        EXPECT_TRUE(fs::exists(out / name)) << name;
    std::ifstream in(out / "results.json");
    const nlohmann::json results = nlohmann::json::parse(in);
    const auto& rows = results.at("rows");
    ASSERT_FALSE(rows.empty());
    size_t exactRows = 0, embreeRows = 0;
    for (const auto& row : rows) {
        const std::string technique = row.at("technique");
        EXPECT_GE(row.at("mrays_per_s").get<double>(), 0.0);
        EXPECT_GE(row.at("steps_mean").get<double>(), 0.0);
        if (row.at("contract") == "exact") {
            ++exactRows;
            EXPECT_LE(row.at("error_max").get<double>(), 1e-3) << technique << " " << row.at("map");
            EXPECT_EQ(row.at("wrong_rate").get<double>(), 0.0) << technique << " " << row.at("map");
        }
        if (technique.rfind("embree", 0) == 0) {
            ++embreeRows;
            EXPECT_LE(row.at("wrong_rate").get<double>(), 1e-3) << technique;
        }
        const std::string images = row.at("images");
        if (!images.empty()) {
            EXPECT_TRUE(fs::exists(out / (images + "-steps.png"))) << images;
        }
    }
    EXPECT_GT(exactRows, 0u);
    EXPECT_GT(embreeRows, 0u);
    std::ifstream csv(out / "results.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("technique,contract,map,backend,elevation,cap,error_mean", 0), 0u);
    size_t lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, rows.size());
    std::ifstream markdown(out / "report.md");
    const std::string report((std::istreambuf_iterator<char>(markdown)), std::istreambuf_iterator<char>());
    EXPECT_NE(report.find("| exact | exact | cpu | 0 | 0 | 0.000 |"), std::string::npos) << report;
    EXPECT_NE(report.find("## Error vs iteration cap"), std::string::npos);
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
}

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(BenchCommand, HtmlReportRendersInHeadlessChromium) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_html_" + std::to_string(::getpid()));
    fs::create_directories(out);
    const std::string log = " > " + (out / "commands.log").string() + " 2>&1";
    ASSERT_EQ(std::system(("command -v chromium" + log).c_str()), 0)
        << "chromium is missing: run scripts/install-deps.sh";
    const std::string bench = std::string(RELIEF_CLI_PATH) + " bench --preset quick --threads 2 --out-dir " +
                              out.string() + log;
    ASSERT_EQ(std::system(bench.c_str()), 0) << bench;
    const std::string chromium = "timeout 120 chromium --headless --no-sandbox --disable-gpu --enable-logging=stderr "
                                 "--v=0 --virtual-time-budget=5000 --user-data-dir=" + (out / "profile").string();
    const std::string page = "file://" + (out / "index.html").string();
    const std::string dump = chromium + " --dump-dom " + page + " > " + (out / "dom.html").string() + " 2> " +
                             (out / "console.log").string();
    ASSERT_EQ(std::system(dump.c_str()), 0) << dump;
    const std::string dom = readText(out / "dom.html");
    EXPECT_NE(dom.find("data-broken-images=\"0\""), std::string::npos) << "some report images did not load";
    EXPECT_EQ(dom.find("data-images=\"0\""), std::string::npos) << "the report has no images";
    const std::string console = readText(out / "console.log");
    EXPECT_EQ(console.find("CONSOLE"), std::string::npos) << console;

    const std::string shot = chromium + " --window-size=1200,900 --screenshot=" + (out / "shot.png").string() + " " +
                             page + log;
    ASSERT_EQ(std::system(shot.c_str()), 0) << shot;
    auto image = relief::loadColorImage((out / "shot.png").string());
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->width, 1200);
    std::set<uint32_t> colours;
    for (const relief::Rgb8& p : image->pixels) colours.insert(uint32_t(p.x) << 16 | uint32_t(p.y) << 8 | p.z);
    EXPECT_GT(colours.size(), 50u) << "the screenshot looks blank";
    fs::remove_all(out);
}

// Every preset (bench-wide and the rows' studies) runs end to end in seconds with --smoke, and
// --judge holds: exact rows and the CPU peers agree with the reference (exit 4 otherwise). On the
// CPU backend here; the GL presets' own smoke run is the ctest bench_gl_presets_smoke (label gl).
TEST(BenchCommand, EveryPresetSmokes) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_smoke_" + std::to_string(::getpid()));
    fs::create_directories(out);
    const std::string list = std::string(RELIEF_CLI_PATH) + " bench --list-presets > " + (out / "presets.txt").string();
    ASSERT_EQ(std::system(list.c_str()), 0) << list;
    std::istringstream presets(readText(out / "presets.txt"));
    size_t count = 0;
    for (std::string line; std::getline(presets, line);) {
        const std::string name = line.substr(0, line.find(' '));
        const fs::path dir = out / name;
        const std::string command = std::string(RELIEF_CLI_PATH) + " bench --preset " + name +
                                    " --smoke --judge --backend cpu --deterministic --no-images --threads 2 --out-dir " +
                                    dir.string() + " > " + (out / (name + ".log")).string() + " 2>&1";
        const int status = std::system(command.c_str());
        EXPECT_EQ(WEXITSTATUS(status), 0) << command << "\n" << readText(out / (name + ".log"));
        EXPECT_TRUE(fs::exists(dir / "report.md")) << name;
        if (fs::exists(dir / "claims.json")) {  // a paper's page: its claims, its parts' rows below it
            std::ifstream in(dir / "claims.json");
            EXPECT_FALSE(nlohmann::json::parse(in).empty()) << name;
            continue;
        }
        std::ifstream in(dir / "results.json");
        EXPECT_FALSE(nlohmann::json::parse(in).at("rows").empty()) << name;
        ++count;
    }
    EXPECT_GE(count, 8u);
    fs::remove_all(out);
}

// Runs `relief bench ARGS` (small, deterministic, no images) into `out`; returns the exit code.
int runBench(const std::string& args, const fs::path& out) {
    const std::string command = std::string(RELIEF_CLI_PATH) + " bench " + args +
                                " --deterministic --no-images --threads 2 --out-dir " + out.string() + " > " +
                                (out.string() + ".log") + " 2>&1";
    return WEXITSTATUS(std::system(command.c_str()));
}

nlohmann::json resultRows(const fs::path& out) {
    std::ifstream in(out / "results.json");
    return nlohmann::json::parse(in).at("rows");
}

// -t NAME:P=V rows are rows of their own, labelled with the variant, with that variant's contract.
TEST(BenchCommand, VariantRowsKeepTheirContracts) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_variants_" + std::to_string(::getpid()));
    ASSERT_EQ(runBench("-t cone,cone:variant=1,relaxed-cone --heightfields gen:fbm:32x32 "
                       "--elevations 40.2 --size 32x32 --caps 8,16",
                       out), 0);
    std::map<std::string, std::set<std::string>> contracts;
    std::map<std::string, std::set<int>> caps;
    for (const auto& row : resultRows(out)) {
        contracts[row.at("technique")].insert(row.at("contract").get<std::string>());
        caps[row.at("technique")].insert(row.at("cap").get<int>());
    }
    EXPECT_EQ(contracts["cone"], std::set<std::string>{"conservative"});
    EXPECT_EQ(contracts["cone:variant=1"], std::set<std::string>{"approximate"});
    EXPECT_EQ(contracts["relaxed-cone"], std::set<std::string>{"approximate"});
    EXPECT_EQ(caps["cone:variant=1"], (std::set<int>{8, 16}));
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
}

// --maps: baked maps give the rows the maps built in the run give; another heightfield is refused.
TEST(BenchCommand, BakedMapsMatchBuiltOnes) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_maps_" + std::to_string(::getpid()));
    fs::create_directories(out);
    const std::string maps = (out / "maps.exr").string();
    const std::string bake = std::string(RELIEF_CLI_PATH) + " bake gen:fbm:32x32 -t cone,safety-sd -o " + maps +
                             " > " + (out / "bake.log").string() + " 2>&1";
    ASSERT_EQ(std::system(bake.c_str()), 0) << bake;
    const std::string common = "-t cone,safety-sd,exact --heightfields gen:fbm:32x32 --elevations 40.2 --size 32x32";
    ASSERT_EQ(runBench(common, out / "built"), 0);
    ASSERT_EQ(runBench(common + " --maps " + maps, out / "baked"), 0);
    auto withoutBuild = [](nlohmann::json rows) {
        for (auto& row : rows) row.erase("bytes_per_texel");
        return rows;
    };
    EXPECT_EQ(withoutBuild(resultRows(out / "built")), withoutBuild(resultRows(out / "baked")));
    EXPECT_EQ(runBench("-t cone --heightfields gen:fbm:48x48 --size 32x32 --maps " + maps, out / "other"), 3);
    fs::remove_all(out);
}

// A Builds study writes one row per technique and map size with its map bytes.
TEST(BenchCommand, BuildsStudyRecordsMaps) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_builds_" + std::to_string(::getpid()));
    ASSERT_EQ(runBench("--preset cones-builds --map-sizes 32,64", out), 0);
    const auto rows = resultRows(out);
    ASSERT_EQ(rows.size(), 12u);  // three builders × two sizes × (fbm, the SRTM window)
    size_t srtm = 0;
    for (const auto& row : rows) srtm += row.at("map") == "earth-srtm-10800x5400@64x64 centre 7980+1860";
    EXPECT_EQ(srtm, 3u);
    for (const auto& row : rows) EXPECT_GT(row.at("bytes_per_texel").get<double>(), 0.0) << row.at("technique");
    std::ifstream md(out / "report.md");
    const std::string report((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
    EXPECT_NE(report.find("## Map builds"), std::string::npos);
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
}

// curves-table1 draws the curves rows with the visibility-curve renderer, as `relief render`
// does: the same Table 1 counts for the same scene, in the JSON, the CSV and the report, with the
// reference traced on every sample's ray.
TEST(BenchCommand, CurvesStudyWritesTable1LikeRender) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_curves_" + std::to_string(::getpid()));
    ASSERT_EQ(runBench("--preset curves-table1 --smoke", out), 0) << readText(out.string() + ".log");
    const fs::path summary = out.string() + "-render.json";
    size_t curvesRows = 0;
    for (const auto& row : resultRows(out)) {
        if (row.at("backend") != "cpu" || row.at("contract") == "peer") continue;
        ++curvesRows;
        EXPECT_GT(row.at("visibility_curves").get<int64_t>(), 0);
        EXPECT_EQ(row.at("total_samples").get<int64_t>(),
                  row.at("inside_samples").get<int64_t>() + row.at("extra_samples").get<int64_t>());
        EXPECT_GT(row.at("reference_cells_per_ray").get<double>(), 0.0);
        const std::string technique = row.at("technique");
        const std::string epsilon = technique.substr(technique.find('=') + 1);
        const std::string render = std::string(RELIEF_CLI_PATH) + " render gen:sine:64x64 -t curves --param epsilon=" +
                                   epsilon + " --elevation " + fmt::format("{}", row.at("elevation").get<double>()) +
                                   " --size 32x32 --format json --deterministic --out-dir " + out.string() +
                                   "-render > " + summary.string() + " 2> " + out.string() + "-render.log";
        ASSERT_EQ(std::system(render.c_str()), 0) << render;
        std::ifstream in(summary);
        const nlohmann::json rendered = nlohmann::json::parse(in).at(0);
        for (const char* count : {"visibility_curves", "inside_samples", "extra_samples", "advance_steps",
                                  "reverse_steps", "binary_cuts", "wall_hits"})
            EXPECT_EQ(row.at(count), rendered.at(count)) << technique << " " << count;
        EXPECT_DOUBLE_EQ(row.at("error_mean").get<double>(), rendered.at("error_mean").get<double>()) << technique;
    }
    EXPECT_EQ(curvesRows, 2u);  // ε = 0.25 and 0.001, one view
    std::ifstream csv(out / "results.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find(",visibility_curves,inside_samples,"), std::string::npos) << header;
    EXPECT_NE(readText(out / "report.md").find("## Visibility curves (Table 1)"), std::string::npos);
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
    fs::remove(summary);
    fs::remove(out.string() + "-render.log");
    fs::remove_all(out.string() + "-render");
}

// A row's TechniqueInfo::mapSummary: extra columns of the builds table, results.csv and .json
// (safety rows: the mean safety distance; exterior-ray maps drop limiting triangles, so their
// distances are never shorter).
TEST(BenchCommand, BuildsStudyWritesMapSummaries) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_summary_" + std::to_string(::getpid()));
    ASSERT_EQ(runBench("--preset safety-exterior-builds --map-sizes 32 -t safety-sd,safety-sd:exterior=1,cone", out), 0);
    std::map<std::string, double> meanR;
    for (const auto& row : resultRows(out))
        if (row.contains("mean_r")) meanR[row.at("technique")] = row.at("mean_r").get<double>();
    ASSERT_EQ(meanR.size(), 2u);  // not cone: it has no map summary
    EXPECT_GT(meanR["safety-sd"], 0.0);
    EXPECT_GE(meanR["safety-sd:exterior=1"], meanR["safety-sd"]);
    std::ifstream csv(out / "results.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find(",mean_r"), std::string::npos) << header;
    std::ifstream md(out / "report.md");
    const std::string report((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
    EXPECT_NE(report.find("| bytes/texel | mean r |"), std::string::npos) << report;
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
}

// A Scaling study plots steps against map size: a curve per row over the maps swept by size (the
// map taken once is no curve), mean steps without the reference, p99 with it.
TEST(BenchCommand, ScalingStudyPlotsStepsAgainstMapSize) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_scaling_" + std::to_string(::getpid()));
    ASSERT_EQ(runBench("--preset quadtree-scaling --map-sizes 16,32,48 --size 16x16 --elevations 15.3 "
                       "-t quadtree,exact --heightfields gen:fbm:{N}x{N}:1,gen:peaks6:24x24",
                       out), 0);
    std::ifstream in(out / "steps_vs_map_size.svg");
    const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    size_t lines = 0;
    for (size_t at = 0; (at = svg.find("<polyline", at)) != std::string::npos; ++at) ++lines;
    EXPECT_EQ(lines, 3u) << svg;  // mean: quadtree; p99: quadtree, exact
    size_t points = 0;
    for (size_t at = 0; (at = svg.find("<circle", at)) != std::string::npos; ++at) ++points;
    EXPECT_EQ(points, 9u);  // three sizes each
    EXPECT_NE(svg.find("Mean steps per ray, 15.3°"), std::string::npos);
    std::ifstream md(out / "report.md");
    const std::string report((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
    EXPECT_NE(report.find("(steps_vs_map_size.svg)"), std::string::npos);
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
}

// A paper's page (--preset qdm): every claim judged from its part's rows. The test recomputes
// each measured claim from the part's results.json (per-view ratios on the same map, view and
// cap, geometric mean; or the mean value) and finds the page's number; verdicts follow the ranges.
TEST(BenchCommand, PaperPageJudgesClaimsFromItsParts) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_paper_" + std::to_string(::getpid()));
    fs::create_directories(out);
    ASSERT_EQ(runBench("--preset qdm --smoke", out), 0) << readText(out.string() + ".log");
    const std::string page = readText(out / "report.md");
    EXPECT_NE(page.find("## Claims"), std::string::npos);
    EXPECT_NE(page.find("(qdm-claims/report.md)"), std::string::npos);
    EXPECT_NE(page.find("GPU: not measured"), std::string::npos);
    std::ifstream in(out / "claims.json");
    const nlohmann::json claims = nlohmann::json::parse(in);
    ASSERT_GE(claims.size(), 10u);
    const nlohmann::json rows = resultRows(out / "qdm-claims");
    auto largestCap = [&](const std::string& technique) {
        int cap = 0;
        for (const auto& r : rows)
            if (r.at("technique") == technique) cap = std::max(cap, r.at("cap").get<int>());
        return cap;
    };
    // Fig. 10 below 45°: steps of the paper's QDM over Dummer's cones at the largest cap.
    double logSum = 0;
    int views = 0;
    for (const auto& n : rows) {
        if (n.at("technique") != "qdm:variant=1" || n.at("cap") != largestCap("qdm:variant=1") ||
            n.at("elevation").get<double>() > 45.0)
            continue;
        for (const auto& d : rows)
            if (d.at("technique") == "cone:variant=1" && d.at("cap") == largestCap("cone:variant=1") &&
                d.at("map") == n.at("map") && d.at("elevation") == n.at("elevation")) {
                logSum += std::log(n.at("steps_mean").get<double>() / d.at("steps_mean").get<double>());
                ++views;
            }
    }
    ASSERT_GT(views, 0);
    bool seenSteps = false, seenPast = false;
    for (const auto& c : claims) {
        const std::string verdict = c.at("verdict");
        EXPECT_TRUE(verdict == "agrees" || verdict == "disagrees" || verdict == "reported" || verdict == "not measured")
            << verdict;
        if (c.at("source") == "Fig. 10" && std::string(c.at("claim")).rfind("below 45°", 0) == 0) {
            seenSteps = true;
            EXPECT_NEAR(c.at("paper_variant").get<double>(), std::exp(logSum / views), 1e-9);
            EXPECT_EQ(verdict, c.at("paper_variant").get<double>() <= 1.0 ? "agrees" : "disagrees");
        }
        if (std::string(c.at("claim")).find("do not enter the surface") != std::string::npos) {
            seenPast = true;
            double sum = 0;
            int n = 0;
            for (const auto& r : rows)
                if (r.at("technique") == "qdm:variant=1" && r.at("cap") == largestCap("qdm:variant=1")) {
                    sum += 100.0 * r.at("past_first_hit_rate").get<double>();
                    ++n;
                }
            EXPECT_NEAR(c.at("paper_variant").get<double>(), sum / n, 1e-9);
            EXPECT_EQ(c.at("safe_variant").get<double>(), 0.0) << "the safe qdm never steps past a hit";
        }
        if (c.at("source") == "Table 1") {
            EXPECT_EQ(verdict, "not measured") << "timings are off in this run";
        }
    }
    EXPECT_TRUE(seenSteps && seenPast);
    fs::remove_all(out);
}

// A study with a shadow light (safety-shadows): every row's shadow test of the reference's points,
// traced from the light, is recorded; the exact rows find the reference's shadows everywhere.
TEST(BenchCommand, ShadowStudyCountsWrongShadows) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_shadow_" + std::to_string(::getpid()));
    fs::create_directories(out);
    ASSERT_EQ(runBench("--preset safety-shadows --heightfields gen:fbm:96x96 --size 64x48", out), 0)
        << readText(out.string() + ".log");
    int exactRows = 0;
    for (const auto& r : resultRows(out)) {
        const double rate = r.at("shadow_wrong_rate");
        if (r.at("contract") == "peer") continue;
        EXPECT_GE(rate, 0.0) << r.at("technique");
        EXPECT_LE(rate, 1.0) << r.at("technique");
        if (r.at("contract") == "exact") {
            EXPECT_EQ(rate, 0.0) << r.at("technique") << " at " << r.at("elevation");
            ++exactRows;
        }
    }
    EXPECT_GE(exactRows, 4);  // safety-sd and safety-cc at two elevations
    fs::remove_all(out);
}

TEST(BenchCommand, RejectsBadOptions) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_bad_" + std::to_string(::getpid()));
    fs::create_directories(out);
    for (const char* args : {"--preset nope", "--caps 0,4", "--size 100x7", "-t nope", "--elevations a,b",
                             "-t cone:variant=7", "-t cone:nope=1", "--preset qdm -t cone",
                             "--preset curves --heightfields gen:fbm:64x64", "--quick --smoke", "-t cone --visibility exterior",
                             "-t cone --phi-max 45", "-t cone --param nope=1", "--edge wrap", "--param x"}) {
        const std::string command = std::string(RELIEF_CLI_PATH) + " bench " + args + " --out-dir " +
                                    (out / "run").string() + " > " + (out / "bad.log").string() + " 2>&1";
        const int status = std::system(command.c_str());
        EXPECT_EQ(WEXITSTATUS(status), 1) << args;
        EXPECT_FALSE(fs::exists(out / "run")) << args << ": a refused run made its output folder";
    }
    fs::remove_all(out);
}

}  // namespace

// --preset cpu-peers (issue 21): every CPU row and both Embree peers time the view's shadow rays
// too (the peers by occlusion queries, which find exact's shadows), safety-cc is skipped on a map
// above 1024², each row's ratios to the peers are paired timings (and the page shows those), and
// the page judges each target from the rows. Timings on: the page is speeds.
TEST(BenchCommand, CpuPeersTimesShadowsAndJudgesTargets) {
    const fs::path out = fs::temp_directory_path() / ("relief_bench_cpu_peers_" + std::to_string(::getpid()));
    const std::string command = std::string(RELIEF_CLI_PATH) +
                                " bench --preset cpu-peers -t safety-cc,exact --heightfields gen:fbm:32x32:1,gen:fbm:1032x1024:1"
                                " --size 32x32 --elevations 40.2 --repeats 1 --no-images --threads 2 --out-dir " +
                                out.string() + " > " + out.string() + ".log 2>&1";
    ASSERT_EQ(WEXITSTATUS(std::system(command.c_str())), 0) << readText(out.string() + ".log");
    std::map<std::string, std::set<std::string>> rowsByMap;
    std::vector<std::string> pairedCells;  // exact's ratios on the 32² map, as the page prints them
    for (const auto& r : resultRows(out)) {
        const std::string technique = r.at("technique");
        rowsByMap[r.at("map")].insert(technique);
        if (r.at("contract") != "peer") {
            ASSERT_TRUE(r.contains("paired_ratios")) << technique;
            const auto& paired = r.at("paired_ratios");
            EXPECT_EQ(paired.size(), 4u) << technique;
            for (const char* query : {"rtcIntersect1", "rtcIntersect16", "rtcOccluded1", "rtcOccluded16"}) {
                ASSERT_TRUE(paired.contains(query)) << technique << " " << query;
                EXPECT_GT(paired.at(query).get<double>(), 0.0) << technique << " " << query;
                if (technique == "exact" && r.at("map") == "fbm:32x32:1")
                    pairedCells.push_back(fmt::format("{:.2f}×", paired.at(query).get<double>()));
            }
        } else {
            EXPECT_FALSE(r.contains("paired_ratios")) << technique;
        }
        ASSERT_TRUE(r.contains("shadow_mrays_per_s")) << technique;
        EXPECT_GT(r.at("shadow_mrays_per_s").get<double>(), 0.0) << technique;
        if (r.at("contract") == "exact") {
            EXPECT_EQ(r.at("shadow_wrong_rate").get<double>(), 0.0);
        }
        if (r.at("contract") == "peer") {
            EXPECT_LE(r.at("shadow_wrong_rate").get<double>(), 1e-3) << technique;
        }
    }
    EXPECT_EQ(rowsByMap["fbm:32x32:1"], (std::set<std::string>{"embree-1", "embree-16", "exact", "safety-cc"}));
    EXPECT_EQ(rowsByMap["fbm:1032x1024:1"], (std::set<std::string>{"embree-1", "embree-16", "exact"}));
    const std::string page = readText(out / "report.md");
    ASSERT_NE(page.find("## CPU peers: targets"), std::string::npos);
    // The every-view table's exact line on the 32² map carries the paired ratios.
    ASSERT_EQ(pairedCells.size(), 4u);
    const size_t line = page.find("| fbm:32x32:1 | 40.2° | exact |");
    ASSERT_NE(line, std::string::npos);
    const std::string exactLine = page.substr(line, page.find('\n', line) - line);
    for (const std::string& cell : pairedCells) EXPECT_NE(exactLine.find("| " + cell + " |"), std::string::npos) << exactLine;
    EXPECT_NE(page.find(fmt::format("ISA: {}", relief::tracerIsa())), std::string::npos);
    int judged = 0, notRun = 0;
    std::istringstream lines(page);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("| ", 0) != 0 || line.find("≥") == std::string::npos) continue;  // a target's line
        judged += line.ends_with("| met |") || line.ends_with("| not met |");
        notRun += line.ends_with("| not run |");
        // safety-cc's targets count the 32² map's view only; exact's both maps'.
        if (line.rfind("| safety-cc", 0) == 0) {
            EXPECT_TRUE(line.find("| 1/1 |") != std::string::npos || line.find("| 0/1 |") != std::string::npos) << line;
        }
        if (line.rfind("| exact", 0) == 0) {
            EXPECT_NE(line.find("/2 |"), std::string::npos) << line;
        }
    }
    EXPECT_EQ(judged, 4);  // safety-cc and exact, primary and shadow
    EXPECT_EQ(notRun, 4);  // quadtree and cone: not among the rows
    fs::remove_all(out);
}
