// maxmip's packet path: taken with the defaults only, and the scalar walk's hits bit for bit (the
// walk itself against the scalar one: quadtree/quadtree_packet_test.cpp, both policies).
#include <gtest/gtest.h>
#include <relief/techniques/common/pyramid_walk_packet.h>
#include <relief/techniques/maxmip/maxmip.h>
#include <relief/techniques/registry.h>
#include <support/packet_test_support.h>
#include <support/walk_test_support.h>

namespace relief {
namespace {

TEST(MaxmipPackets, RegistryMaxmipUsesPacketsForDefaultsOnly) {
    for (const EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const auto surface = walk_test::makeSurface({"fbm", 64, 48, edge, 0.2f});
        walk_test::RayMaker maker(*surface, 5);
        const std::vector<Ray> rays = maker.all(100);
        const MaxmipTracer scalar(surface, std::make_shared<const MaxPyramid>(*surface), {});
        using Overrides = std::vector<std::pair<std::string, double>>;
        const Overrides cases[] = {{}, {{"max-steps", 8}}, {{"bits", 16}}, {{"box-surface", 1}}};
        for (const Overrides& overrides : cases) {
            const std::string what = overrides.empty() ? "defaults" : overrides[0].first;
            auto tracer = createTracer("maxmip", surface, overrides);
            ASSERT_TRUE(tracer.ok()) << what;
            const bool isScalar =
                dynamic_cast<const BatchTracer<MaxmipTracer>*>(tracer->get()) != nullptr;
            EXPECT_EQ(isScalar, !overrides.empty() || !packetsEnabled()) << what;
            if (!overrides.empty()) continue;
            std::vector<Hit> hits(rays.size());
            traceAll(**tracer, rays, hits);
            for (size_t k = 0; k < rays.size(); ++k) {
                const Hit want = scalar.trace(rays[k]);
                EXPECT_TRUE(packet_test::identical(hits[k], want)) << walk_test::describe(rays[k]);
            }
        }
    }
}

}  // namespace
}  // namespace relief
