// Loads by lane for the packet walks, per Highway target (the -inl.h convention of
// cell_test-inl.h): one value per lane (GatherLanes) or two neighbours per lane (GatherPairs).
// On AVX2 these are scalar loads put together in registers instead of vgather, which is
// microcoded and slow on first-generation Zen: there the loads made each walk 1–24 % faster
// (docs/benchmarks-packets.md, "Loads by lane"; other AVX2 CPUs not measured). Highway has no
// such option (its AVX2 GatherIndex is the instruction), so it is written here. SSE4 (emulated
// by Highway already) and AVX-512 (fast gathers on the machines measured) keep GatherIndex.
#if defined(RELIEF_SURFACE_LANE_GATHER_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SURFACE_LANE_GATHER_INL_H_
#undef RELIEF_SURFACE_LANE_GATHER_INL_H_
#else
#define RELIEF_SURFACE_LANE_GATHER_INL_H_
#endif

#include <hwy/highway.h>

#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace lane_gather {
namespace hn = hwy::HWY_NAMESPACE;

#if HWY_TARGET == HWY_AVX2
template <class D>
constexpr bool kByLoads = hn::MaxLanes(D()) == 8;
#else
template <class D>
constexpr bool kByLoads = false;
#endif

// base[index[k]] in lane k (T: float or int32_t).
template <class D, class T = hn::TFromD<D>>
HWY_INLINE hn::Vec<D> GatherLanes(D d, const T* HWY_RESTRICT base,
                                  hn::Vec<hn::RebindToSigned<D>> index) {
    if constexpr (kByLoads<D>) {
        alignas(32) int32_t at[8];
        hn::Store(index, hn::RebindToSigned<D>(), at);
        alignas(32) T values[8];
        for (int k = 0; k < 8; ++k) values[k] = base[at[k]];
        return hn::Load(d, values);
    } else {
        return hn::GatherIndex(d, base, index);
    }
}

// base[index[k]] in first's lane k and base[index[k] + 1] in second's.
template <class DF>
HWY_INLINE void GatherPairs(DF df, const float* HWY_RESTRICT base,
                            hn::Vec<hn::RebindToSigned<DF>> index, hn::Vec<DF>& first,
                            hn::Vec<DF>& second) {
    const hn::RebindToSigned<DF> di;
    if constexpr (kByLoads<DF>) {
#if HWY_TARGET == HWY_AVX2
        alignas(32) int32_t at[8];
        hn::Store(index, di, at);
        long long q[8];
        for (int k = 0; k < 8; ++k) std::memcpy(&q[k], base + at[k], sizeof(long long));
        // a: lanes 0, 1 | 4, 5 and b: lanes 2, 3 | 6, 7, each as (value, next) pairs; the
        // shuffles take the values, then the next ones, in lane order.
        const __m256 a = _mm256_castsi256_ps(_mm256_set_epi64x(q[5], q[4], q[1], q[0]));
        const __m256 b = _mm256_castsi256_ps(_mm256_set_epi64x(q[7], q[6], q[3], q[2]));
        first = hn::Vec<DF>{_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))};
        second = hn::Vec<DF>{_mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1))};
#endif
    } else {
        first = hn::GatherIndex(df, base, index);
        second = hn::GatherIndex(df, base, hn::Add(index, hn::Set(di, 1)));
    }
}

}  // namespace lane_gather
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SURFACE_LANE_GATHER_INL_H_
