// The vector types of the packet walks (surface/cell_walk_packet.cpp, cone/cone_packet.cpp,
// common/pyramid_walk_packet.cpp, safety_cc/safety_cc_packet.cpp), per Highway target (the -inl.h
// convention of cell_test-inl.h): a lane per ray, floats and int32 of the same width, the size of
// the lane arrays that hold the lanes' state between vector passes, and what the walks do lane
// by lane (a lane's ray into the arrays, prefetches by lane, a loop over the lanes of a mask).
#if defined(RELIEF_SURFACE_PACKET_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SURFACE_PACKET_LANES_INL_H_
#undef RELIEF_SURFACE_PACKET_LANES_INL_H_
#else
#define RELIEF_SURFACE_PACKET_LANES_INL_H_
#endif

#include <hwy/cache_control.h>
#include <hwy/highway.h>
#include <relief/core/math.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace packet_lanes {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::CappedTag<float, 16>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;
using MI = hn::Mask<DI>;
constexpr size_t kLanes = 16;  // array size; a target uses Lanes(DF()) ≤ 16 of them

// A lane's ray into a packet's arrays ox, oy, oz, dx, dy, dz.
template <class Packet>
void setLaneRay(Packet& p, size_t lane, const Ray& ray) {
    p.ox[lane] = ray.origin.x;
    p.oy[lane] = ray.origin.y;
    p.oz[lane] = ray.origin.z;
    p.dx[lane] = ray.direction.x;
    p.dy[lane] = ray.direction.y;
    p.dz[lane] = ray.direction.z;
}

// A lane's ray and cellsHit's per-ray constants (cell_walk.h: the step per axis, 1/d and the
// exit side's offset), into a packet's arrays of those names.
// invX, invY: 1 / d.x and 1 / d.y, where the caller has them already.
template <class Packet>
void setCellWalkRay(Packet& p, size_t lane, const Ray& ray, float invX, float invY) {
    setLaneRay(p, lane, ray);
    const vec3& d = ray.direction;
    p.stepX[lane] = d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0);
    p.stepY[lane] = d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0);
    p.invX[lane] = invX;
    p.invY[lane] = invY;
    p.exitX[lane] = p.stepX[lane] > 0 ? 1.5f : 0.5f;
    p.exitY[lane] = p.stepY[lane] > 0 ? 1.5f : 0.5f;
}

template <class Packet>
void setCellWalkRay(Packet& p, size_t lane, const Ray& ray) {
    setCellWalkRay(p, lane, ray, 1.0f / ray.direction.x, 1.0f / ray.direction.y);
}

// Asks for the line of base[index] in every lane ahead of its gather: the packet walks know an
// address a pass before they load it (Highway has no gather-prefetch; a prefetch only costs an
// issue slot, and every lane's index must be inside base's array).
template <class T>
HWY_INLINE void PrefetchLanes(const T* base, VI index) {
    const DI di;
    alignas(64) int32_t ahead[kLanes];
    hn::Store(index, di, ahead);
    // The lanes' indices are read back from memory: left to itself the compiler takes them out
    // of the register one by one (two micro-ops each on the family-23 EPYC), and a prefetch is
    // on no critical path, so the store's latency costs nothing (2–8 % on the pyramid walk and
    // the cone march there, docs/benchmarks-packets.md). The empty asm only says "ahead may have
    // changed" (GCC and Clang).
    asm("" : "+m"(ahead));
    for (size_t k = 0; k < hn::Lanes(di); ++k) hwy::Prefetch(base + ahead[k]);
}

// f(k) for every lane k set in `lanes`, in lane order: the scalar parts of the packet walks
// visit the few lanes that end a ray, not all of them (a branch per lane mispredicts).
template <class F>
HWY_INLINE void ForEachLane(uint64_t lanes, F&& f) {  // lane k: bit k
    for (; lanes != 0; lanes &= lanes - 1) f(size_t(std::countr_zero(lanes)));
}

template <class F>
HWY_INLINE void ForEachLane(MI lanes, F&& f) {
    uint8_t bytes[8] = {};
    hn::StoreMaskBits(DI(), lanes, bytes);
    uint64_t bits = 0;
    std::memcpy(&bits, bytes, sizeof(bits));
    ForEachLane(bits, f);
}

// Batched blocks: where a block of a walk (a cell test, a probe) costs a whole vector's work
// however few lanes need it, the lanes that need it wait, their state unchanged, until a batch of
// them do. BatchOf: `eighths` eighths of the target's lanes, at least one (each walk measured its
// share on AVX2, docs/benchmarks-packets.md); BatchReady: whether the lanes `waiting` take the
// block now, a batch of them or every active lane (then nothing else would move).
inline size_t BatchOf(size_t eighths) {
    return std::max<size_t>(1, hn::Lanes(DF()) * eighths / 8);
}

HWY_INLINE bool BatchReady(MI waiting, MI active, size_t batch) {
    const size_t count = hn::CountTrue(DI(), waiting);
    return count >= batch || count == hn::CountTrue(DI(), active);
}

}  // namespace packet_lanes
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SURFACE_PACKET_LANES_INL_H_
