// relief <command> [options]: the command table. Each command lives in cmd_<name>.cpp.
#include <relief/cli/common.h>
#include <relief/core/isa.h>
#include <relief/core/memory_budget.h>
#include <relief/core/progress.h>
#include <relief/io/output.h>

#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <memory>

namespace relief::cli {

void addCommands(CLI::App& app) {
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("relief ") + RELIEF_VERSION + " (tracer ISA: " +
                                          std::string(tracerIsa()) + ")");
    // A flag callback rather than a bound variable: nothing outlives the app (fuzz_cli replaces
    // the app's parse-complete callback).
    app.add_flag_callback("-q,--quiet", [] { relief::Progress::setQuiet(true); }, "no progress output")
        ->configurable(false);
    addInfoCommand(app);
    addTraceCommand(app);
    addRaysCommand(app);
    addRenderCommand(app);
    addBakeCommand(app);
    addBenchCommand(app);
    addViewCommand(app);
    addServeCommand(app);
    addHelpCommand(app);
}

}  // namespace relief::cli

namespace relief::cli {

int runCommandLine(int argc, char** argv) {
    CLI::App app{"relief: heightfield ray casting, the published methods side by side"};
    setMemoryBudget(defaultMemoryBudget());  // a previous command line in this process may have set it
    // A bad RELIEF_ISA is an error like a bad option, before anything runs (core/isa.h).
    if (const Status isa = checkIsaEnvironment(); !isa) return report(isa.error());
    addCommands(app);
    // Output lost on a full disk, a closed pipe or a closed stdout is an I/O error, not exit 0.
    const auto finish = [](int code) {
        const Status flushed = flushStdout();
        return code == 0 && !flushed ? report(flushed.error()) : code;
    };
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return finish(app.exit(e));
    } catch (const CLI::CallForAllHelp& e) {
        return finish(app.exit(e));
    } catch (const CLI::CallForVersion& e) {
        return finish(app.exit(e));
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "relief: error: %s\n", e.what());
        std::fprintf(stderr, "run 'relief --help' or 'relief COMMAND --help' for usage\n");
        return 1;
    } catch (const CommandFailed& failure) {
        return report(failure.error);
    } catch (const std::bad_alloc&) {
        return report({relief::ErrorKind::Runtime, "out of memory"});
    }
    return finish(0);
}

}  // namespace relief::cli

// RELIEF_CLI_NO_MAIN: the CLI linked into another program (fuzz/fuzz_cli.cpp with libFuzzer's
// main, the toy-technique test), which calls runCommandLine or addCommands itself.
#ifndef RELIEF_CLI_NO_MAIN
int main(int argc, char** argv) {
    // A closed stdin/stdout/stderr must not be reused by the first file opened (an output's temp
    // would receive the text meant for stdout): hold it with a descriptor that cannot be written.
    for (int fd = 0; fd <= 2; ++fd)
        if (::fcntl(fd, F_GETFD) == -1 && ::open("/dev/null", O_RDONLY) != fd) return 2;
    // A reader that closed early is EPIPE, reported with the path, not a silent death.
    std::signal(SIGPIPE, SIG_IGN);
    return relief::cli::runCommandLine(argc, argv);
}
#endif
