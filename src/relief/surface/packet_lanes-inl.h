// The vector types of the packet walks (surface/cell_walk_packet.cpp, cone/cone_packet.cpp,
// common/pyramid_walk_packet.cpp), per Highway target (the -inl.h convention of
// cell_test-inl.h): a lane per ray, floats and int32 of the same width, and the size of the
// lane arrays that hold the lanes' state between vector passes.
#if defined(RELIEF_SURFACE_PACKET_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SURFACE_PACKET_LANES_INL_H_
#undef RELIEF_SURFACE_PACKET_LANES_INL_H_
#else
#define RELIEF_SURFACE_PACKET_LANES_INL_H_
#endif

#include <hwy/highway.h>

#include <cstddef>

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

}  // namespace packet_lanes
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SURFACE_PACKET_LANES_INL_H_
