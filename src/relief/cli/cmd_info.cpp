#include <relief/cli/common.h>
namespace relief::cli {
void addInfoCommand(CLI::App&) {}
}
