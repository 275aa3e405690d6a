// relief help [COMMAND]: the command list and the technique table from the registry.
#include <relief/cli/common.h>
#include <relief/techniques/registry.h>

#include <iostream>

namespace relief::cli {

void addHelpCommand(CLI::App& app) {
    auto topic = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("help", "commands, techniques and their contracts");
    cmd->add_option("command", *topic, "show the options of this command");
    cmd->callback([&app, topic] {
        if (!topic->empty()) {
            CLI::App* sub = nullptr;
            try {
                sub = app.get_subcommand(*topic);
            } catch (const CLI::OptionNotFound&) {
                throw CommandFailed{makeError(ErrorKind::BadArgument, "help: no command '{}'", *topic)};
            }
            std::cout << sub->help();
            return;
        }
        // The formatter, not app.help(): that shows the selected subcommand's help, i.e. this
        // command's own, instead of the command list.
        std::cout << app.get_formatter()->make_help(&app, app.get_name(),
                                                    CLI::AppFormatMode::Normal)
                  << "\nTechniques (-t NAME):\n";
        for (const TechniqueInfo& info : techniques()) {
            std::cout << fmt::format("  {:<18} {:<13} {}\n", info.name, toString(info.contract),
                                     info.summary);
            for (const ParamSpec& p : info.params)
                std::cout << fmt::format("  {:<18}   --param {}={} [{} to {}, {}] ({})\n", "",
                                         p.name, p.defaultValue, p.minValue, p.maxValue,
                                         toString(p.role), p.help);
            for (const VariantSpec& v : info.variants)
                std::cout << fmt::format("  {:<18}   variant {} ({}): {}, {}{}\n", "", v.label,
                                         v.params, toString(v.contract), v.summary,
                                         v.clampOnly ? " (clamp mode only)" : "");
            if (!info.shaderFunction.empty())
                std::cout << fmt::format("  {:<18}   shader function {} (shaders/relief/{})\n", "",
                                         info.shaderFunction, info.shaderFile);
        }
        std::cout << "\nA variant is its own row in relief bench: -t NAME:PARAM=V[:PARAM=V].\n"
                     "An exact row with its iteration cap set (N > 0 where 0 means none) is "
                     "approximate.\n";
        std::cout << "\nExit codes: 0 ok, 1 bad arguments, 2 I/O, 3 invalid input, 4 runtime/GL, "
                     "5 unsupported.\n";
    });
}

}  // namespace relief::cli
