// relief <command> [options]: the command table. Each command lives in cmd_<name>.cpp.
#include <relief/cli/common.h>
#include <relief/core/progress.h>

#include <cstdio>
#include <memory>

namespace relief::cli {

void addCommands(CLI::App& app) {
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("relief ") + RELIEF_VERSION);
    // A flag callback rather than a bound variable: nothing outlives the app (fuzz_cli replaces
    // the app's parse-complete callback).
    app.add_flag_callback("-q,--quiet", [] { relief::Progress::setQuiet(true); }, "no progress output")
        ->configurable(false);
    addInfoCommand(app);
    addTraceCommand(app);
    addRenderCommand(app);
    addBakeCommand(app);
    addBenchCommand(app);
    addViewCommand(app);
    addHelpCommand(app);
}

}  // namespace relief::cli

namespace relief::cli {

int runCommandLine(int argc, char** argv) {
    CLI::App app{"relief: heightfield ray casting, the published methods side by side"};
    addCommands(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "relief: error: %s\n", e.what());
        std::fprintf(stderr, "run 'relief --help' or 'relief COMMAND --help' for usage\n");
        return 1;
    } catch (const CommandFailed& failure) {
        return report(failure.error);
    } catch (const std::bad_alloc&) {
        return report({relief::ErrorKind::Runtime, "out of memory"});
    }
    return 0;
}

}  // namespace relief::cli

// RELIEF_CLI_NO_MAIN: the CLI linked into another program (fuzz/fuzz_cli.cpp with libFuzzer's
// main, the toy-technique test), which calls runCommandLine or addCommands itself.
#ifndef RELIEF_CLI_NO_MAIN
int main(int argc, char** argv) { return relief::cli::runCommandLine(argc, argv); }
#endif
