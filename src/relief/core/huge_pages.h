#pragma once
// Asks the kernel to back a large, already written array with 2 MiB pages (Linux transparent huge
// pages, madvise MADV_COLLAPSE). The tracers gather from maps of tens of MiB at scattered texels;
// with 4 KiB pages nearly every gather of a 4096² map misses the TLB, and the page walks sit on the
// march's critical path. Embree allocates its BVH the same way on Linux.
// Best effort: a kernel without MADV_COLLAPSE (before 6.1), THP switched off, or too little
// contiguous memory leaves the array on small pages, with the same contents; nothing else changes.
#include <cstddef>

namespace relief {

// The whole 2 MiB pages inside [data, data + bytes); arrays under 4 MiB are left alone.
void adviseHugePages(const void* data, size_t bytes);

}  // namespace relief
