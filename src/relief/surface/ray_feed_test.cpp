// The packet walks' ray feed (ray_feed-inl.h) on every Highway target this machine has: the SIMD
// clip gives Surface::clip's span bit for bit (empty ones included) for the contract maps' ray
// families and for rays clip refuses (NaN, infinities, no direction, tMax ≤ 0 or NaN, origins
// beyond kMaxOriginCoordinate, denormal and zero components, origins on the faces); the feed hands
// out exactly the rays that enter the box, in order, and answers the others with an empty hit.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "relief/surface/ray_feed_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>
#include <relief/surface/ray_feed-inl.h>

#include <span>
#include <vector>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// ClipRays over the whole multiple of the lane count, then the feed over every ray.
void ClipAndFeed(const Surface& s, std::span<const Ray> rays, std::vector<RayInterval>& clipped,
                 std::vector<size_t>& fed, std::vector<Hit>& hits) {
    const hn::ScalableTag<float> df;
    const size_t whole = rays.size() / hn::Lanes(df) * hn::Lanes(df);
    std::vector<float> tEnter(whole), tExit(whole);
    ray_feed::ClipRays(df, s, rays.data(), whole, tEnter.data(), tExit.data());
    clipped.resize(whole);
    for (size_t k = 0; k < whole; ++k) clipped[k] = {tEnter[k], tExit[k]};
    ray_feed::RayFeed feed(s, rays, hits);
    size_t index;
    RayInterval span;
    while (feed.next(index, span)) fed.push_back(index);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <gtest/gtest.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

#include <bit>
#include <cmath>
#include <limits>

namespace relief {
HWY_EXPORT(ClipAndFeed);
namespace {

// Rays clip refuses or that sit on its edge cases, around a box of w × h × depth.
std::vector<Ray> oddRays(float w, float h, float depth) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
    const float tiny = std::numeric_limits<float>::denorm_min();
    const vec3 inside(w * 0.5f, h * 0.5f, depth * 0.5f);
    const vec3 above(w * 0.5f, h * 0.5f, depth * 2.0f + 1.0f);
    std::vector<Ray> rays = {
        {vec3(nan, 1.0f, 1.0f), vec3(0.0f, 0.0f, -1.0f)},
        {inside, vec3(nan, 0.0f, -1.0f)},
        {vec3(inf, 1.0f, 1.0f), vec3(-1.0f, 0.0f, 0.0f)},
        {inside, vec3(0.0f, 0.0f, 0.0f)},
        {inside, vec3(inf, 0.0f, 0.0f)},
        {inside, vec3(0.0f, 0.0f, -1.0f), 0.0f},
        {inside, vec3(0.0f, 0.0f, -1.0f), -1.0f},
        {inside, vec3(0.0f, 0.0f, -1.0f), nan},
        {inside, vec3(0.0f, 0.0f, -1.0f), 0.25f},
        {vec3(-1e9f, 1.0f, 1.0f), vec3(1.0f, 0.0f, 0.0f)},
        {vec3(float(1 << 28), 1.0f, 1.0f), vec3(-1.0f, 0.0f, 0.0f)},
        {vec3(-float(1 << 27), h * 0.5f, depth * 0.5f), vec3(1.0f, 0.0f, 0.0f)},
        {above, vec3(tiny, 0.0f, -1.0f)},
        {above, vec3(tiny, -tiny, -1.0f)},
        {vec3(0.0f, 0.0f, 0.0f), vec3(0.6f, 0.8f, 0.0f)},
        {vec3(w, h, depth), vec3(-0.6f, -0.8f, 0.0f)},
        {vec3(0.0f, h * 0.5f, depth), vec3(0.0f, 0.0f, 1.0f)},
        {vec3(w * 0.5f, -1.0f, depth * 0.5f), vec3(0.0f, 1.0f, 0.0f)},
        {vec3(w * 0.5f, -1.0f, depth * 0.5f), vec3(0.0f, -1.0f, 0.0f)},
        {inside, vec3(0.3f, 0.4f, 0.866f)},
        {above, vec3(0.3f, 0.4f, 0.866f)},
        {vec3(w * 0.5f, h * 0.5f, -5.0f), vec3(0.0f, 0.0f, 1.0f)},
        {vec3(w * 0.5f, h * 0.5f, -5.0f), vec3(0.001f, 0.0f, 0.001f)},
    };
    return rays;
}

bool sameBits(const RayInterval& a, const RayInterval& b) {
    return std::bit_cast<uint32_t>(a.tEnter) == std::bit_cast<uint32_t>(b.tEnter) &&
           std::bit_cast<uint32_t>(a.tExit) == std::bit_cast<uint32_t>(b.tExit);
}

TEST(RayFeed, SimdClipIsClipBitForBitAndTheFeedSkipsTheMisses) {
    packet_test::forEachTarget([] {
        size_t rays = 0, differences = 0;
        uint32_t seed = 3;
        for (const walk_test::MapSpec& m : walk_test::contractMaps()) {
            const auto surface = walk_test::makeSurface(m, seed);
            walk_test::RayMaker maker(*surface, seed++);
            std::vector<Ray> batch = maker.all(200);
            const std::vector<Ray> odd =
                oddRays(float(surface->width()), float(surface->height()), surface->depth());
            batch.insert(batch.end(), odd.begin(), odd.end());
            std::vector<RayInterval> clipped;
            std::vector<size_t> fed;
            std::vector<Hit> hits(batch.size());
            for (Hit& hit : hits) hit.steps = -1;  // the feed answers every miss
            HWY_DYNAMIC_DISPATCH(ClipAndFeed)(*surface, batch, clipped, fed, hits);
            std::vector<size_t> entering;
            for (size_t k = 0; k < batch.size(); ++k) {
                const RayInterval want = surface->clip(batch[k]);
                ++rays;
                if (k < clipped.size() && !sameBits(clipped[k], want)) {
                    if (differences++ < 5)
                        ADD_FAILURE() << walk_test::describe(m) << " "
                                      << walk_test::describe(batch[k]) << ": clip ["
                                      << want.tEnter << ", " << want.tExit << "], SIMD ["
                                      << clipped[k].tEnter << ", " << clipped[k].tExit << "]";
                }
                if (!want.empty()) {
                    entering.push_back(k);
                } else {
                    EXPECT_FALSE(hits[k].hit);
                    EXPECT_EQ(hits[k].steps, 0) << "a miss the feed did not answer";
                }
            }
            EXPECT_EQ(fed, entering) << walk_test::describe(m);
        }
        EXPECT_GE(rays, 100000u);
        EXPECT_EQ(differences, 0u);
    });
}

}  // namespace
}  // namespace relief
#endif  // HWY_ONCE
