#include <relief/core/huge_pages.h>

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace relief {

void adviseHugePages(const void* data, size_t bytes) {
#if defined(__linux__)
    constexpr uintptr_t kHugePage = uintptr_t(2) << 20;
    constexpr int kCollapse = 25;  // MADV_COLLAPSE (Linux 6.1); Debian 12's headers predate it
    if (data == nullptr || bytes < 2 * kHugePage) return;
    const uintptr_t begin = (uintptr_t(data) + kHugePage - 1) & ~(kHugePage - 1);
    const uintptr_t end = (uintptr_t(data) + bytes) & ~(kHugePage - 1);
    if (end <= begin) return;
    // Errors (EINVAL on older kernels, EAGAIN/ENOMEM when no 2 MiB page is free) are the
    // documented fallback: the pages stay as they are.
    (void)madvise(reinterpret_cast<void*>(begin), end - begin, kCollapse);
#else
    (void)data;
    (void)bytes;
#endif
}

}  // namespace relief
