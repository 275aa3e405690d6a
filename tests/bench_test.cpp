// `relief bench --preset quick` on tiny inputs: the outputs exist and parse, and the numbers are
// sane (exact and the exact-contract techniques have zero error, Embree agrees with exact).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
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
        if (!images.empty()) EXPECT_TRUE(fs::exists(out / (images + "-steps.png"))) << images;
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
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
}

TEST(BenchCommand, RejectsBadOptions) {
    for (const char* args : {"--preset nope", "--caps 0,4", "--size 100x7", "-t nope", "--elevations a,b"}) {
        const std::string command = std::string(RELIEF_CLI_PATH) + " bench " + args + " --out-dir /nonexistent-relief >/dev/null 2>&1";
        const int status = std::system(command.c_str());
        EXPECT_EQ(WEXITSTATUS(status), 1) << args;
    }
}

}  // namespace
