// Adding a technique (docs/architecture.md): one row registered, and the CLI, the contract harness
// and the bench serve it with no other change. The row is registered before main(), as a plug-in
// linked into the relief program would be.
#include "toy_technique.h"

#include <support/contract_harness.h>

#include <relief/cli/common.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace relief {
namespace {

namespace fs = std::filesystem;

// The same tracer claiming a promise it cannot keep: the harness must catch it.
const TechniqueInfo kOverclaimingRow = [] {
    TechniqueInfo row = toy::kMarchRow;
    row.name = "toy-march-claims-exact";
    row.contract = Contract::Exact;
    return row;
}();

const bool kRegistered = [] {
    bool ok = true;
    for (const TechniqueInfo* row : {&toy::kMarchRow, &kOverclaimingRow}) {
        const Status status = registerTechnique(*row);
        if (!status) std::fprintf(stderr, "%s\n", status.error().message.c_str());
        ok = ok && status.ok();
    }
    return ok;
}();

class ToyTechnique : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(kRegistered);
        m_dir = fs::temp_directory_path() /
                ("relief-toy-" + std::to_string(::getpid()) + "-" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    // `relief ARGS` in this process; {tmp} stands for the test's folder.
    int relief(std::string args) {
        for (size_t at; (at = args.find("{tmp}")) != std::string::npos;)
            args.replace(at, 5, m_dir.string());
        std::vector<std::string> words{"relief"};
        std::istringstream in(args);
        for (std::string w; in >> w;) words.push_back(w);
        std::vector<char*> argv;
        for (std::string& w : words) argv.push_back(w.data());
        return cli::runCommandLine(int(argv.size()), argv.data());
    }
    std::string read(const std::string& name) const {
        std::ifstream in(m_dir / name);
        return {std::istreambuf_iterator<char>(in), {}};
    }

    fs::path m_dir;
};

TEST_F(ToyTechnique, RegistryServesIt) {
    const TechniqueInfo* info = findTechnique("toy-march");
    ASSERT_NE(info, nullptr);
    EXPECT_NE(techniqueNames().find("toy-march"), std::string::npos);
    EXPECT_FALSE(registerTechnique(toy::kMarchRow)) << "a second row of the same name";
    EXPECT_EQ(contractOf(*info, *resolveParams(*info, {})), Contract::Approximate);
}

TEST_F(ToyTechnique, CliServesIt) {
    std::ofstream(m_dir / "rays.csv") << "ox,oy,oz,dx,dy,dz\n16,16,40,0,0,-1\n-5,16,3,1,0,0\n";
    EXPECT_EQ(relief("trace gen:peaks6:32x32 -t toy-march --rays {tmp}/rays.csv -o {tmp}/hits.csv"), 0);
    const std::string hits = read("hits.csv");
    EXPECT_NE(hits.find("\n1,"), std::string::npos) << hits;  // the vertical ray hits
    EXPECT_EQ(relief("trace gen:peaks6:32x32 -t toy-march --max-steps 8 --param step=0.5 "
                     "--rays {tmp}/rays.csv -o {tmp}/capped.csv"), 0);
    EXPECT_EQ(relief("render gen:peaks6:32x32 -t toy-march,exact --size 32x24 --out-dir {tmp}/r "
                     "--deterministic"), 0);
    EXPECT_TRUE(fs::exists(m_dir / "r"));
    // Its parameters are checked like any row's.
    EXPECT_EQ(relief("trace gen:peaks6:32x32 -t toy-march --param step=9 --rays {tmp}/rays.csv"), 1);
    EXPECT_EQ(relief("trace gen:peaks6:32x32 -t toy-march --phi-max 30 --rays {tmp}/rays.csv"), 1);
}

TEST_F(ToyTechnique, ContractHarnessServesIt) {
    const testing::ContractRun run = testing::runContractHarness(*findTechnique("toy-march"));
    ASSERT_TRUE(run.error.empty()) << run.error;
    EXPECT_EQ(run.contract, Contract::Approximate);
    EXPECT_GE(run.tally.rays, 100000u);
    EXPECT_TRUE(testing::keepsContract(run));
    EXPECT_LT(run.tally.sumError / double(run.tally.bothHit), 1.0) << "a reasonable march";
    // Claimed exact, the same tracer is caught on some map (thin spikes, grazing rays).
    const testing::ContractRun claimed =
        testing::runContractHarness(*findTechnique("toy-march-claims-exact"));
    EXPECT_EQ(claimed.contract, Contract::Exact);
    EXPECT_FALSE(testing::keepsContract(claimed));
    EXPECT_FALSE(claimed.brokenOn.empty());
}

TEST_F(ToyTechnique, BenchServesIt) {
    EXPECT_EQ(relief("bench --preset quick -t toy-march,toy-march:step=1,exact --deterministic "
                     "--no-images --threads 2 --out-dir {tmp}/bench"), 0);
    const std::string csv = read("bench/results.csv");
    EXPECT_NE(csv.find("\ntoy-march,approximate,"), std::string::npos) << csv;
    EXPECT_NE(csv.find("\ntoy-march:step=1,approximate,"), std::string::npos) << csv;
    EXPECT_NE(read("bench/report.md").find("toy-march"), std::string::npos);
}

// docs/architecture.md describes every folder of the library and the walk-through this test is.
TEST(Architecture, DocumentNamesEveryFolder) {
    std::ifstream in(fs::path(RELIEF_SOURCE_DIR) / "docs/architecture.md");
    const std::string doc{std::istreambuf_iterator<char>(in), {}};
    ASSERT_FALSE(doc.empty());
    for (const auto& entry : fs::directory_iterator(fs::path(RELIEF_SOURCE_DIR) / "src/relief")) {
        if (entry.is_directory()) {
            EXPECT_NE(doc.find("| `" + entry.path().filename().string() + "/` |"), std::string::npos)
                << entry.path().filename() << " is not in the folder table";
        }
    }
    EXPECT_NE(doc.find("tests/toy/"), std::string::npos);
}

}  // namespace
}  // namespace relief
