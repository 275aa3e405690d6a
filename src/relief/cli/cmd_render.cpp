#include <relief/cli/common.h>
namespace relief::cli {
void addRenderCommand(CLI::App&) {}
}
