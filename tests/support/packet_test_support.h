#pragma once
// Test support for the SIMD packet paths (quadtree, maxmip, exact) and the ISA dispatch: hits
// compared bit for bit, and a check run once per Highway target this machine has.
#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <relief/core/math.h>
#include <relief/techniques/common/pyramid_walk_packet.h>

#include <bit>
#include <cstdint>

namespace relief::packet_test {

// Every field of the hit, floats by their bits.
inline bool identical(const Hit& a, const Hit& b) {
    const auto bits = [](float v) { return std::bit_cast<uint32_t>(v); };
    return a.hit == b.hit && bits(a.t) == bits(b.t) && bits(a.position.x) == bits(b.position.x) &&
           bits(a.position.y) == bits(b.position.y) &&
           bits(a.position.z) == bits(b.position.z) && a.steps == b.steps &&
           a.fetches == b.fetches;
}

// `run` once per compiled target this machine has (AVX-512, AVX2, SSE4, the fallback), with the
// dispatch forced to it.
template <class Run>
void forEachTarget(Run run) {
    const int64_t supported = hwy::SupportedTargets();
    for (const int64_t target :
         {int64_t(HWY_AVX3), int64_t(HWY_AVX2), int64_t(HWY_SSE4), int64_t(HWY_EMU128)}) {
        if ((supported & target) == 0) continue;
        hwy::SetSupportedTargetsForTest(target);
        SCOPED_TRACE(packetWalkTarget());
        run();
    }
    hwy::SetSupportedTargetsForTest(0);
}

}  // namespace relief::packet_test
