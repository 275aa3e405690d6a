// libFuzzer target: the option parser of every `relief` command (the command table of
// src/relief/cli/main.cpp, CLI11 with the commands' checks and conversions). The input is the
// argument list, NUL-separated, after "relief". The top-level parse-complete callback, which
// CLI11 runs after every option is parsed and checked and before any command's callback, stops
// the run: this target parses, it never loads or renders. (The commands' callbacks must stay:
// they own the storage their options write to.) Seeds: fuzz/corpus/cli/.
#include <relief/cli/common.h>

#include <algorithm>
#include <string>
#include <vector>

namespace {
struct ParsedOnly {};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace relief::cli;
    std::vector<std::string> args{"relief"};
    const char* text = reinterpret_cast<const char*>(data);
    for (size_t start = 0; start <= size && args.size() <= 64;) {
        const size_t end = size_t(std::find(text + start, text + size, '\0') - text);
        args.emplace_back(text + start, end - start);
        start = end + 1;
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());

    CLI::App app{"relief"};
    addCommands(app);
    app.parse_complete_callback([] { throw ParsedOnly{}; });
    try {
        app.parse(int(argv.size()), argv.data());
    } catch (const ParsedOnly&) {
    } catch (const CLI::CallForHelp&) {
        (void)app.help();  // the formatter runs over every option of the app
    } catch (const CLI::CallForAllHelp&) {
        (void)app.help("", CLI::AppFormatMode::All);
    } catch (const CLI::CallForVersion&) {
    } catch (const CLI::ParseError& e) {
        // Every refusal says what is wrong.
        if (std::string(e.what()).empty()) __builtin_trap();
    }
    return 0;
}
