#include <relief/core/huge_pages.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace relief {
namespace {

// Whatever the kernel does with the advice (collapse, refuse, not know it), the array's contents
// and size stay as they were: the tracers read it right after.
TEST(HugePages, ContentsSurviveTheAdvice) {
    std::vector<uint32_t> values(size_t(9) << 20 >> 2);  // 9 MiB: whole 2 MiB pages inside
    for (size_t k = 0; k < values.size(); ++k) values[k] = uint32_t(k * 2654435761u);
    adviseHugePages(values.data(), values.size() * sizeof(uint32_t));
    for (size_t k = 0; k < values.size(); ++k) ASSERT_EQ(values[k], uint32_t(k * 2654435761u)) << k;
    values[values.size() / 2] = 7u;  // still writable
    EXPECT_EQ(values[values.size() / 2], 7u);
}

TEST(HugePages, SmallUnalignedAndEmptyRangesAreLeftAlone) {
    std::vector<float> small(1000, 1.5f);
    adviseHugePages(small.data() + 1, (small.size() - 1) * sizeof(float));
    adviseHugePages(nullptr, size_t(64) << 20);
    adviseHugePages(small.data(), 0);
    for (float v : small) ASSERT_EQ(v, 1.5f);
}

}  // namespace
}  // namespace relief
