#include <relief/core/memory_budget.h>

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <charconv>
#include <limits>

namespace relief {

namespace {

std::atomic<int64_t>& budget() {
    static std::atomic<int64_t> value{defaultMemoryBudget()};
    return value;
}

}  // namespace

int64_t defaultMemoryBudget() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || pageSize <= 0) return int64_t(4) << 30;
    return int64_t(pages) * int64_t(pageSize) / 2;
}

int64_t memoryBudget() { return budget().load(); }
void setMemoryBudget(int64_t bytes) { budget().store(bytes); }

Result<int64_t> parseMemorySize(std::string_view text) {
    const auto bad = [&] {
        return makeError(ErrorKind::BadArgument,
                         "--max-memory '{}': expected BYTES or a number with K, M or G "
                         "(e.g. 512M, 4G), at least 1M",
                         text);
    };
    int64_t value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || value <= 0) return bad();
    std::string_view suffix(ptr, size_t(end - ptr));
    if (!suffix.empty() && (suffix.back() == 'B' || suffix.back() == 'b') && suffix.size() <= 2)
        suffix.remove_suffix(1);
    int shift = 0;
    if (suffix.size() == 1) {
        switch (std::tolower(static_cast<unsigned char>(suffix[0]))) {
        case 'k': shift = 10; break;
        case 'm': shift = 20; break;
        case 'g': shift = 30; break;
        default: return bad();
        }
    } else if (!suffix.empty()) {
        return bad();
    }
    if (value > (std::numeric_limits<int64_t>::max() >> shift)) return bad();
    value <<= shift;
    // Less than a megabyte cannot even hold the program's own tables.
    if (value < (int64_t(1) << 20)) return bad();
    return value;
}

std::string formatBytes(int64_t bytes) {
    if (bytes >= (int64_t(1) << 30)) return fmt::format("{:.1f} GiB", double(bytes) / double(1 << 30));
    if (bytes >= (int64_t(1) << 20)) return fmt::format("{:.1f} MiB", double(bytes) / double(1 << 20));
    return fmt::format("{} bytes", bytes);
}

Status reserveMemory(int64_t bytes, std::string_view what) {
    const int64_t limit = memoryBudget();
    if (bytes >= 0 && bytes <= limit) return {};
    return makeError(ErrorKind::InvalidInput,
                     "{}: needs about {}, over the memory budget of {} (raise it with "
                     "--max-memory SIZE, e.g. --max-memory {}G)",
                     what, bytes < 0 ? std::string("more than can be counted") : formatBytes(bytes),
                     formatBytes(limit),
                     bytes < 0 ? int64_t(0) : (bytes + (int64_t(1) << 30) - 1) >> 30);
}

}  // namespace relief
