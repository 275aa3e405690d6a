#pragma once
// One process-wide memory budget (--max-memory): readers, builders and the renderer ask it before
// a large allocation, so that an input too big for the machine is refused with the estimate
// instead of being paged to death or killed. Each check covers one step's peak on its own; the
// estimates are not summed across steps.
#include <relief/core/error.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace relief {

// Half of physical memory (sysconf), or 4 GiB where the system does not say.
int64_t defaultMemoryBudget();
int64_t memoryBudget();
void setMemoryBudget(int64_t bytes);

// "BYTES", "NNNK", "NNNM", "NNNG" (powers of 1024, optional trailing B, case-insensitive).
Result<int64_t> parseMemorySize(std::string_view text);
std::string formatBytes(int64_t bytes);

// InvalidInput when `bytes` (an estimate; negative = overflowed) exceeds the budget; `what` names
// the allocation ("path: decoding 16384x16384 16-bit RGBA"), the message gives estimate, budget and
// the option that raises it.
Status reserveMemory(int64_t bytes, std::string_view what);

}  // namespace relief
