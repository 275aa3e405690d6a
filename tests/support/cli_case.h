#pragma once
// One CLI case as data: arguments, expected exit code, fragments of stdout and stderr. The
// command-line case tables (tests/cli_test.cpp, tests/memory_budget_test.cpp) run their rows here.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <utility>

namespace relief::testing {

struct CliCase {
    const char* name;
    std::string args;  // after "relief"; {tmp} and {src} are substituted
    int exitCode;
    const char* stdoutFragment;
    const char* stderrFragment;
};

inline std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Runs the case with its output in `tmp` (stdout.txt, stderr.txt) and checks it.
inline void runCliCase(const CliCase& c, const std::filesystem::path& tmp) {
    std::string args = c.args;
    for (auto [key, value] : {std::pair<std::string, std::string>{"{tmp}", tmp.string()},
                              {"{src}", RELIEF_SOURCE_DIR}})
        for (size_t p; (p = args.find(key)) != std::string::npos;) args.replace(p, key.size(), value);
    const std::filesystem::path out = tmp / "stdout.txt", err = tmp / "stderr.txt";
    const std::string command = std::string(RELIEF_CLI_PATH) + " " + args + " >" + out.string() +
                                " 2>" + err.string();
    const int status = std::system(command.c_str());
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    const std::string stdoutText = readFile(out), stderrText = readFile(err);
    EXPECT_EQ(code, c.exitCode) << c.name << ": relief " << args << "\nstderr: " << stderrText;
    EXPECT_NE(stdoutText.find(c.stdoutFragment), std::string::npos)
        << c.name << ": stdout lacks '" << c.stdoutFragment << "':\n" << stdoutText;
    EXPECT_NE(stderrText.find(c.stderrFragment), std::string::npos)
        << c.name << ": stderr lacks '" << c.stderrFragment << "':\n" << stderrText;
}

}  // namespace relief::testing
