// How the packet walks (surface/cell_walk_packet.cpp, cone/cone_packet.cpp,
// safety_cc/safety_cc_packet.cpp, common/pyramid_walk_packet.cpp) hand a batch's rays to their
// lanes, per Highway target (the -inl.h convention of cell_test-inl.h): in batch order, each ray
// that misses the box answered at once (an empty hit), the next one that enters it given with its
// clipped span. The spans are clipped a chunk of rays at a time in SIMD (ClipRays), the same
// float operations in the same order as Surface::clip, so every span is clip's bit for bit; the
// rays two chunks ahead are prefetched (the clip's gathers otherwise wait on memory: a batch of
// rays streams through once).
#if defined(RELIEF_SURFACE_RAY_FEED_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SURFACE_RAY_FEED_INL_H_
#undef RELIEF_SURFACE_RAY_FEED_INL_H_
#else
#define RELIEF_SURFACE_RAY_FEED_INL_H_
#endif

#include <hwy/cache_control.h>
#include <hwy/highway.h>
#include <relief/surface/lane_gather-inl.h>
#include <relief/surface/surface.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace ray_feed {
namespace hn = hwy::HWY_NAMESPACE;

// The gathers read a ray as 7 floats: origin, direction, tMax.
static_assert(sizeof(Ray) == 7 * sizeof(float));

// A ray's field c (0-2 origin, 3-5 direction, 6 tMax) across lanes, for the lanes' rays
// rays[first + lane].
template <class DF>
HWY_INLINE hn::Vec<DF> GatherRayField(DF df, const Ray* rays, size_t first, int32_t c) {
    const hn::RebindToSigned<DF> di;
    const auto index = hn::Mul(hn::Iota(di, 0), hn::Set(di, 7));
    return lane_gather::GatherLanes(df, &rays[first].origin.x, hn::Add(index, hn::Set(di, c)));
}

// Surface::clip for rays[0, count), count a multiple of Lanes(df): tEnter and tExit per ray
// (RayInterval{} = {0, -1} where clip returns it).
template <class DF>
HWY_INLINE void ClipRays(DF df, const Surface& s, const Ray* rays, size_t count, float* tEnter,
                         float* tExit) {
    using VF = hn::Vec<DF>;
    const VF zero = hn::Zero(df), minusOne = hn::Set(df, -1.0f), one = hn::Set(df, 1.0f);
    const VF limit = hn::Set(df, Surface::kMaxOriginCoordinate);
    const VF depth = hn::Set(df, s.depth()), maxZ = hn::Set(df, s.maxZ());
    const bool clamp = s.edge() == EdgeMode::Clamp;
    const VF width = hn::Set(df, float(s.width())), height = hn::Set(df, float(s.height()));
    const VF travel =
        hn::Set(df, Surface::kRepeatTravelFactor * float(std::max(s.width(), s.height())));
    const size_t lanes = hn::Lanes(df);
    for (size_t k = 0; k < count; k += lanes) {
        const auto field = [&](int32_t c) { return GatherRayField(df, rays, k, c); };
        const VF ox = field(0), oy = field(1), oz = field(2);
        const VF dx = field(3), dy = field(4), dz = field(5), tMax = field(6);
        // clip's refusals: not finite, no direction, tMax not > 0, too far away.
        auto valid = hn::And(hn::And(hn::And(hn::IsFinite(ox), hn::IsFinite(oy)),
                                     hn::And(hn::IsFinite(oz), hn::IsFinite(dx))),
                             hn::And(hn::IsFinite(dy), hn::IsFinite(dz)));
        valid = hn::AndNot(hn::And(hn::And(hn::Eq(dx, zero), hn::Eq(dy, zero)), hn::Eq(dz, zero)),
                           valid);
        valid = hn::And(valid, hn::Gt(tMax, zero));
        valid = hn::And(valid, hn::Not(hn::Gt(hn::Max(hn::Max(hn::Abs(ox), hn::Abs(oy)), hn::Abs(oz)),
                                               limit)));
        VF lo = zero, hi = tMax;
        auto inside = valid;
        // clipSlab, in clip's order. A slab the ray is parallel to leaves [lo, hi] as it is and
        // asks for the origin inside; otherwise lo ≤ hi after the last slab implies it after
        // each (lo only grows, hi only shrinks, neither becomes NaN), which is clip's answer.
        const auto slab = [&](VF origin, VF direction, VF a, VF b) {
            const auto parallel = hn::Eq(direction, zero);
            const VF inv = hn::Div(one, direction);
            const VF ta = hn::Mul(hn::Sub(a, origin), inv), tb = hn::Mul(hn::Sub(b, origin), inv);
            const auto swap = hn::Gt(ta, tb);  // t0, t1: the pair in order
            const VF t0 = hn::IfThenElse(swap, tb, ta), t1 = hn::IfThenElse(swap, ta, tb);
            lo = hn::IfThenElse(hn::And(hn::Not(parallel), hn::Lt(lo, t0)), t0, lo);  // std::max
            hi = hn::IfThenElse(hn::And(hn::Not(parallel), hn::Lt(t1, hi)), t1, hi);  // std::min
            const auto within = hn::And(hn::Ge(origin, a), hn::Le(origin, b));
            inside = hn::AndNot(hn::AndNot(within, parallel), inside);
        };
        slab(oz, dz, zero, depth);
        if (clamp) {
            slab(ox, dx, zero, width);
            slab(oy, dy, zero, height);
        }
        inside = hn::And(inside, hn::Le(lo, hi));
        if (!clamp) {  // the horizontal travel allowed in repeat mode
            const VF horizontal = hn::Sqrt(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)));
            const VF reach = hn::Div(travel, horizontal);
            hi = hn::IfThenElse(hn::And(hn::Gt(horizontal, zero), hn::Lt(reach, hi)), reach, hi);
        }
        // Above the highest sample and rising: nothing can be hit.
        VF top = hn::Div(hn::Sub(maxZ, oz), dz);
        top = hn::IfThenElse(hn::Lt(lo, top), top, lo);                              // std::max
        hi = hn::IfThenElse(hn::And(hn::Gt(dz, zero), hn::Lt(top, hi)), top, hi);  // std::min
        hn::StoreU(hn::IfThenElse(inside, lo, zero), df, tEnter + k);
        hn::StoreU(hn::IfThenElse(inside, hi, minusOne), df, tExit + k);
    }
}

// A batch's rays for the lanes of a packet walk: next() gives the next ray that enters the box
// (its index and span) and answers the ones that miss it with Hit{}.
class RayFeed {
public:
    RayFeed(const Surface& s, std::span<const Ray> rays, std::span<Hit> hits)
        : m_s(s), m_rays(rays), m_hits(hits) {}

    // False once the batch is done.
    bool next(size_t& index, RayInterval& span) {
        for (;;) {
            if (m_next == m_clipped && !clipChunk()) return false;
            const size_t i = m_next++;
            span = {m_tEnter[i - m_chunk], m_tExit[i - m_chunk]};
            if (!span.empty()) {
                index = i;
                return true;
            }
            m_hits[i] = Hit{};
        }
    }

    static constexpr size_t kChunk = 64;  // a multiple of every target's lane count
    static constexpr size_t kAheadChunks = 2;  // how far ahead of its clip a chunk is prefetched

    // The chunk the last next() came from: its first ray's index, one past its last, and the
    // spans of its rays (entry k is ray chunkBegin() + k; empty where the ray misses the box).
    size_t chunkBegin() const { return m_chunk; }
    size_t chunkEnd() const { return m_clipped; }
    const float* chunkEnter() const { return m_tEnter; }
    const float* chunkExit() const { return m_tExit; }

private:

    bool clipChunk() {
        if (m_next >= m_rays.size()) return false;
        const hn::ScalableTag<float> df;
        const size_t lanes = hn::Lanes(df);
        const size_t count = std::min(kChunk, m_rays.size() - m_next);
        const size_t whole = count / lanes * lanes;
        prefetchRays(m_next + kAheadChunks * kChunk);
        ClipRays(df, m_s, m_rays.data() + m_next, whole, m_tEnter, m_tExit);
        for (size_t k = whole; k < count; ++k) {  // the tail: clip itself
            const RayInterval span = m_s.clip(m_rays[m_next + k]);
            m_tEnter[k] = span.tEnter;
            m_tExit[k] = span.tExit;
        }
        m_chunk = m_next;
        m_clipped = m_next + count;
        return true;
    }

    // The rays of the chunk that starts at `first`, asked for ahead of its clip: the clip
    // gathers them field by field, and a batch's rays (28 bytes each) stream from memory.
    void prefetchRays(size_t first) const {
        if (first >= m_rays.size()) return;
        const size_t count = std::min(kChunk, m_rays.size() - first);
        const char* begin = reinterpret_cast<const char*>(m_rays.data() + first);
        const char* end = reinterpret_cast<const char*>(m_rays.data() + first + count);
        for (const char* line = begin; line < end; line += 64) hwy::Prefetch(line);
    }

    const Surface& m_s;
    std::span<const Ray> m_rays;
    std::span<Hit> m_hits;
    size_t m_next = 0, m_chunk = 0, m_clipped = 0;
    alignas(64) float m_tEnter[kChunk], m_tExit[kChunk];
};

}  // namespace ray_feed
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SURFACE_RAY_FEED_INL_H_
