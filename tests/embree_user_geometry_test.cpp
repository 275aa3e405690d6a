// The heightfield as an Embree user geometry (embree/heightfield_geometry.h) against the same
// heightfield triangulated (attachSolidMesh) on one Embree device, through Embree's own calls
// (rtcIntersect1/4/8/16, rtcOccluded1/16) with tnear/tfar limits, on 10^5+ rays over fbm, an
// adversarial generator and a real map. Behind `exact` the user geometry must give exactly what
// relief's exact tracer gives, and agree with the triangles except where Embree's triangle test is
// the one that is off (judged by the brute force, as in exact_test.cpp). Behind `cone`
// (conservative) it never reports a hit past exact's.
#include <support/brute_force.h>
#include <support/ray_sets.h>

#include <relief/core/generators.h>
#include <relief/embree/embree_scene.h>
#include <relief/embree/heightfield_geometry.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace relief {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// What one Embree query returned for one ray.
struct EmbreeHit {
    bool hit = false;
    float t = kInf;
    vec3 ng{0.0f};
    float u = 0, v = 0;
    unsigned geomID = RTC_INVALID_GEOMETRY_ID, primID = RTC_INVALID_GEOMETRY_ID;
};

// Bit-exact, so that a failing ray can be replayed.
std::string rayText(const Ray& r) {
    return fmt::format("ray o=({:a}, {:a}, {:a}) d=({:a}, {:a}, {:a})", r.origin.x, r.origin.y, r.origin.z,
                       r.direction.x, r.direction.y, r.direction.z);
}

struct Segment {
    Ray ray;  // ray.tMax is tfar
    float tnear = 0.0f;
};

// Embree's packet types by width; width 1 has the same memory layout as RTCRayHitN with N = 1.
template <int N> struct Packet;
template <> struct Packet<1> {
    using RayHit = RTCRayHit;
    using RayOnly = RTCRay;
    static void intersect(const int*, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect1(s, c, r); }
    static void occluded(const int*, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded1(s, c, r); }
};
template <> struct Packet<4> {
    using RayHit = RTCRayHit4;
    using RayOnly = RTCRay4;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect4(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded4(v, s, c, r); }
};
template <> struct Packet<8> {
    using RayHit = RTCRayHit8;
    using RayOnly = RTCRay8;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect8(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded8(v, s, c, r); }
};
template <> struct Packet<16> {
    using RayHit = RTCRayHit16;
    using RayOnly = RTCRay16;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect16(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) { rtcOccluded16(v, s, c, r); }
};

// Fills lane i of an RTCRayN of width N; `scale` stretches the direction (t shrinks by as much),
// so that the callbacks see directions of any length.
void setLane(RTCRayN* r, unsigned N, unsigned i, const Segment& s, float scale) {
    RTCRayN_org_x(r, N, i) = s.ray.origin.x;
    RTCRayN_org_y(r, N, i) = s.ray.origin.y;
    RTCRayN_org_z(r, N, i) = s.ray.origin.z;
    RTCRayN_dir_x(r, N, i) = scale * s.ray.direction.x;
    RTCRayN_dir_y(r, N, i) = scale * s.ray.direction.y;
    RTCRayN_dir_z(r, N, i) = scale * s.ray.direction.z;
    RTCRayN_tnear(r, N, i) = s.tnear / scale;
    RTCRayN_tfar(r, N, i) = s.ray.tMax / scale;
    RTCRayN_time(r, N, i) = 0.0f;
    RTCRayN_mask(r, N, i) = 0xFFFFFFFFu;
    RTCRayN_id(r, N, i) = i;
    RTCRayN_flags(r, N, i) = 0;
}

// Every segment through the scene in packets of N (the last one partly valid); t in units of the
// unscaled direction.
template <int N>
std::vector<EmbreeHit> intersectAll(RTCScene scene, const std::vector<Segment>& segments, float scale = 1.0f) {
    std::vector<EmbreeHit> out(segments.size());
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t first = 0; first < segments.size(); first += N) {
        const unsigned n = unsigned(std::min<size_t>(N, segments.size() - first));
        alignas(64) int valid[N];
        alignas(64) typename Packet<N>::RayHit rh;
        RTCRayN* rays = RTCRayHitN_RayN(reinterpret_cast<RTCRayHitN*>(&rh), N);
        RTCHitN* hits = RTCRayHitN_HitN(reinterpret_cast<RTCRayHitN*>(&rh), N);
        for (unsigned i = 0; i < unsigned(N); ++i) {
            valid[i] = i < n ? -1 : 0;
            setLane(rays, N, i, segments[first + std::min(i, n - 1)], scale);
            RTCHitN_geomID(hits, N, i) = RTC_INVALID_GEOMETRY_ID;
            RTCHitN_instID(hits, N, i, 0) = RTC_INVALID_GEOMETRY_ID;
        }
        Packet<N>::intersect(valid, scene, &context, &rh);
        for (unsigned i = 0; i < n; ++i) {
            EmbreeHit& h = out[first + i];
            h.geomID = RTCHitN_geomID(hits, N, i);
            if (h.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            h.hit = true;
            h.t = RTCRayN_tfar(rays, N, i) * scale;
            h.ng = vec3(RTCHitN_Ng_x(hits, N, i), RTCHitN_Ng_y(hits, N, i), RTCHitN_Ng_z(hits, N, i));
            h.u = RTCHitN_u(hits, N, i);
            h.v = RTCHitN_v(hits, N, i);
            h.primID = RTCHitN_primID(hits, N, i);
        }
    }
    return out;
}

template <int N>
std::vector<char> occludedAll(RTCScene scene, const std::vector<Segment>& segments) {
    std::vector<char> out(segments.size());
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t first = 0; first < segments.size(); first += N) {
        const unsigned n = unsigned(std::min<size_t>(N, segments.size() - first));
        alignas(64) int valid[N];
        alignas(64) typename Packet<N>::RayOnly r;
        RTCRayN* rays = reinterpret_cast<RTCRayN*>(&r);
        for (unsigned i = 0; i < unsigned(N); ++i) {
            valid[i] = i < n ? -1 : 0;
            setLane(rays, N, i, segments[first + std::min(i, n - 1)], 1.0f);
        }
        Packet<N>::occluded(valid, scene, &context, &r);
        for (unsigned i = 0; i < n; ++i) out[first + i] = RTCRayN_tfar(rays, N, i) == -kInf;
    }
    return out;
}

// One device with two committed scenes: the solid's triangles, and the user geometry over
// `technique`.
class Scenes {
public:
    Scenes(std::shared_ptr<const Surface> surface, std::string_view technique = "exact") {
        m_device = rtcNewDevice(nullptr);
        m_triangles = rtcNewScene(m_device);
        rtcSetSceneFlags(m_triangles, RTC_SCENE_FLAG_ROBUST);
        auto mesh = attachSolidMesh(m_triangles, *surface);
        RELIEF_CHECK(mesh.ok());
        rtcCommitScene(m_triangles);
        m_user = rtcNewScene(m_device);
        auto geometry = embree::attachHeightfield(m_user, surface, technique);
        RELIEF_CHECK(geometry.ok());
        m_geometry.emplace(std::move(*geometry));
        rtcCommitScene(m_user);
    }
    ~Scenes() {
        m_geometry.reset();
        rtcReleaseScene(m_user);
        rtcReleaseScene(m_triangles);
        rtcReleaseDevice(m_device);
    }
    RTCScene triangles() const { return m_triangles; }
    RTCScene user() const { return m_user; }
    unsigned geomID() const { return m_geometry->geomID(); }

private:
    RTCDevice m_device;
    RTCScene m_triangles, m_user;
    std::optional<embree::HeightfieldGeometry> m_geometry;
};

struct MapUnderTest {
    std::string label;
    std::shared_ptr<const Surface> surface;
};

std::shared_ptr<const Surface> surfaceOf(Heightfield hf) {
    const float depth = 0.25f * float(std::max(hf.width, hf.height));
    return std::make_shared<const Surface>(std::make_shared<const Heightfield>(std::move(hf)), depth,
                                           EdgeMode::Clamp);
}

// fbm, an adversarial generator (one-texel walls and pillars) and a real map (a 400² DEM from
// ../shared/data when present, else the repository's).
std::vector<MapUnderTest> mapsUnderTest() {
    std::vector<MapUnderTest> maps;
    maps.push_back({"fbm 160x128", surfaceOf(*generateHeightfield("fbm", 160, 128, 3))});
    maps.push_back({"walls 96x96", surfaceOf(*generateHeightfield("walls", 96, 96, 5))});
    const std::string shared = RELIEF_SOURCE_DIR "/../shared/data/finland-topography-400-16bit.png";
    const std::string path = std::filesystem::exists(shared) ? shared : RELIEF_SOURCE_DIR "/data/colorado-elevation-400.png";
    auto real = loadHeightfield(path);
    RELIEF_CHECK(real.ok());
    maps.push_back({std::filesystem::path(path).stem().string(), surfaceOf(std::move(*real))});
    return maps;
}

// The reference's answer restricted to [tnear, tfar] (tnear is drawn below the first hit, so the
// first hit past tnear is the first hit).
bool inSegment(const Hit& ref, const Segment& s) { return ref.hit && ref.t >= s.tnear && ref.t <= s.ray.tMax; }
// A hit this close to an end of the segment may fall either side of it by rounding.
bool nearEnd(const Hit& ref, const Segment& s) {
    return ref.hit && (std::abs(ref.t - s.tnear) < 1e-3f || std::abs(ref.t - s.ray.tMax) < 1e-3f);
}

// Unlimited segments, and the same rays with tnear in [0, 0.9 t_ref] and tfar cutting about
// half of the hits off.
std::vector<Segment> segmentsOf(const std::vector<Ray>& rays, const std::vector<Hit>& ref, bool limited, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Segment> segments;
    for (size_t k = 0; k < rays.size(); ++k) {
        Segment s{rays[k], 0.0f};
        if (limited) {
            const float reach = ref[k].hit ? ref[k].t : 100.0f;
            s.tnear = 0.9f * reach * unit(rng);
            s.ray.tMax = k % 3 == 0 ? kInf : s.tnear + 2.0f * (reach - s.tnear) * unit(rng);
        }
        segments.push_back(s);
    }
    return segments;
}

struct Agreement {
    size_t rays = 0, agree = 0, explained = 0, limited = 0, unexplained = 0;
};

// User geometry (a) against triangles (b): agreement, and disagreements the brute force puts on
// Embree's triangle test (or on float rounding of an ill-conditioned ray).
void compareWithTriangles(const BruteForceTracer& oracle, const std::vector<Segment>& segments,
                          const std::vector<EmbreeHit>& a, const std::vector<EmbreeHit>& b, Agreement& tally) {
    for (size_t k = 0; k < segments.size(); ++k) {
        ++tally.rays;
        if (sameAnswer(a[k].hit, a[k].t, b[k].hit, b[k].t)) {
            ++tally.agree;
            continue;
        }
        if (segments[k].tnear > 0.0f || segments[k].ray.tMax < kInf) {
            ++tally.limited;  // judged against exact on the same segment instead (the strict check)
            continue;
        }
        const Disagreement kind = classifyDisagreement(oracle, segments[k].ray, a[k].hit, a[k].t, b[k].hit, b[k].t);
        if (kind == Disagreement::Unexplained) {
            ++tally.unexplained;
            ADD_FAILURE() << rayText(segments[k].ray) << ": user geometry " << a[k].hit << " t=" << a[k].t
                          << ", triangles " << b[k].hit << " t=" << b[k].t;
        } else {
            ++tally.explained;
        }
    }
}

TEST(EmbreeUserGeometry, MatchesExactAndTheTrianglesOnRandomRays) {
    size_t rays = 0, strict = 0, occludedChecked = 0;
    Agreement one, sixteen, limitedOne, limitedSixteen;
    uint32_t seed = 11;
    for (const MapUnderTest& map : mapsUnderTest()) {
        const Surface& s = *map.surface;
        const Scenes scenes(map.surface);
        const BruteForceTracer oracle(s);
        auto exact = createTracer("exact", map.surface);
        ASSERT_TRUE(exact.ok());
        testing::RaySets sets(s, seed++);
        std::vector<Ray> batch = sets.all(12000);  // 36000 rays per map
        // Not those from below the base: they enter through the solid's bottom face, outside DESIGN
        // §3 (o above S or on the box boundary), where relief's tracers promise nothing.
        std::erase_if(batch, [](const Ray& r) { return r.origin.z < 0.0f; });
        std::vector<Hit> ref(batch.size());
        (*exact)->traceBatch(batch, ref);
        for (bool limited : {false, true}) {
            const std::vector<Segment> segments = segmentsOf(batch, ref, limited, seed++);
            const auto user1 = intersectAll<1>(scenes.user(), segments);
            const auto user16 = intersectAll<16>(scenes.user(), segments);
            const auto tri1 = intersectAll<1>(scenes.triangles(), segments);
            const auto tri16 = intersectAll<16>(scenes.triangles(), segments);
            const auto occUser1 = occludedAll<1>(scenes.user(), segments);
            const auto occUser16 = occludedAll<16>(scenes.user(), segments);
            for (size_t k = 0; k < segments.size(); ++k) {
                ++rays;
                // The exact contract against relief's exact tracer on the same segment.
                if (!nearEnd(ref[k], segments[k])) {
                    const bool expected = inSegment(ref[k], segments[k]);
                    for (const EmbreeHit* h : {&user1[k], &user16[k]}) {
                        ++strict;
                        ASSERT_TRUE(sameAnswer(h->hit, h->t, expected, ref[k].t))
                            << map.label << " " << rayText(segments[k].ray) << " tnear " << segments[k].tnear
                            << " tfar " << segments[k].ray.tMax << ": user geometry " << h->hit << " t=" << h->t
                            << ", exact " << ref[k].hit << " t=" << ref[k].t;
                    }
                    ASSERT_EQ(bool(occUser1[k]), expected) << map.label << " " << rayText(segments[k].ray);
                    ASSERT_EQ(bool(occUser16[k]), expected) << map.label << " " << rayText(segments[k].ray);
                    occludedChecked += 2;
                }
                if (user1[k].hit) {
                    const vec3 p = segments[k].ray.at(user1[k].t);
                    ASSERT_EQ(user1[k].geomID, scenes.geomID());
                    ASSERT_EQ(user1[k].primID, 0u);
                    EXPECT_NEAR(user1[k].u, p.x, 1e-3f * std::max(1.0f, user1[k].t));
                    EXPECT_NEAR(user1[k].v, p.y, 1e-3f * std::max(1.0f, user1[k].t));
                    EXPECT_NEAR(glm::length(user1[k].ng), 1.0f, 1e-3f);
                }
            }
            compareWithTriangles(oracle, segments, user1, tri1, limited ? limitedOne : one);
            compareWithTriangles(oracle, segments, user16, tri16, limited ? limitedSixteen : sixteen);
            // Occlusion on the triangles: the same answer wherever their intersect agreed.
            const auto occTri1 = occludedAll<1>(scenes.triangles(), segments);
            const auto occTri16 = occludedAll<16>(scenes.triangles(), segments);
            for (size_t k = 0; k < segments.size(); ++k)
                if (sameAnswer(user1[k].hit, user1[k].t, tri1[k].hit, tri1[k].t) && !nearEnd(ref[k], segments[k])) {
                    EXPECT_EQ(occUser1[k], occTri1[k]) << map.label << " " << rayText(segments[k].ray);
                    EXPECT_EQ(occUser16[k], occTri16[k]) << map.label << " " << rayText(segments[k].ray);
                }
        }
    }
    for (auto [label, a] : {std::pair{"rtcIntersect1", one}, {"rtcIntersect16", sixteen},
                            {"rtcIntersect1 tnear/tfar", limitedOne}, {"rtcIntersect16 tnear/tfar", limitedSixteen}}) {
        std::printf("[ user geometry vs triangles, %s ] %zu rays, %zu agree, %zu disagree: %zu explained by the "
                    "brute force, %zu limited segments (checked against exact)\n",
                    label, a.rays, a.agree, a.rays - a.agree, a.explained, a.limited);
        EXPECT_EQ(a.unexplained, 0u) << label;
        EXPECT_GE(double(a.agree), 0.999 * double(a.rays)) << label;
    }
    std::printf("[ user geometry vs exact ] %zu segments, %zu intersect and %zu occluded answers checked\n", rays,
                strict, occludedChecked);
    EXPECT_GE(rays, size_t(100000));
}

// Packet widths 4 and 8, and directions that are not unit length (as an instance's transform
// leaves them): t comes back in the caller's units.
TEST(EmbreeUserGeometry, AnyPacketWidthAndDirectionLength) {
    const auto surface = surfaceOf(*generateHeightfield("terraces", 64, 48, 2));
    const Scenes scenes(surface);
    testing::RaySets sets(*surface, 4);
    const std::vector<Ray> batch = sets.all(700);
    std::vector<Hit> ref(batch.size());
    auto exact = createTracer("exact", surface);
    ASSERT_TRUE(exact.ok());
    (*exact)->traceBatch(batch, ref);
    const std::vector<Segment> segments = segmentsOf(batch, ref, false, 1);
    for (const auto& hits : {intersectAll<4>(scenes.user(), segments), intersectAll<8>(scenes.user(), segments),
                             intersectAll<16>(scenes.user(), segments, 2.5f), intersectAll<1>(scenes.user(), segments, 0.3f)})
        for (size_t k = 0; k < segments.size(); ++k)
            ASSERT_TRUE(sameAnswer(hits[k].hit, hits[k].t, ref[k].hit, ref[k].t))
                << rayText(batch[k]) << ": " << hits[k].hit << " t=" << hits[k].t << ", exact " << ref[k].t;
}

// Placed in a world by an Embree instance (texel space scaled by 0.5 and moved): the hit is
// exact's on the ray in texel space, t in world units, and the hit names the instance.
TEST(EmbreeUserGeometry, PlacedByAnInstance) {
    const auto surface = surfaceOf(*generateHeightfield("peaks6", 48, 40, 3));
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene local = rtcNewScene(device), world = rtcNewScene(device);
    auto attached = embree::attachHeightfield(local, surface);
    ASSERT_TRUE(attached.ok());
    std::optional<embree::HeightfieldGeometry> geometry(std::move(*attached));
    rtcCommitScene(local);
    constexpr float kScale = 0.5f;
    const vec3 offset(100.0f, -20.0f, 3.0f);
    const float xfm[12] = {kScale, 0, 0, 0, kScale, 0, 0, 0, kScale, offset.x, offset.y, offset.z};  // column-major 3×4
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, local);
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(instance);
    const unsigned instanceID = rtcAttachGeometry(world, instance);
    rtcReleaseGeometry(instance);
    rtcCommitScene(world);

    testing::RaySets sets(*surface, 9);
    std::vector<Segment> segments;
    const std::vector<Ray> texelRays = sets.fromOutside(2000);
    for (const Ray& r : texelRays) segments.push_back({Ray{offset + kScale * r.origin, r.direction, kInf}, 0.0f});
    auto exact = createTracer("exact", surface);
    ASSERT_TRUE(exact.ok());
    std::vector<Hit> ref(texelRays.size());
    (*exact)->traceBatch(texelRays, ref);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    size_t hits = 0;
    for (size_t k = 0; k < segments.size(); ++k) {
        RTCRayHit rh{};
        setLane(reinterpret_cast<RTCRayN*>(&rh.ray), 1, 0, segments[k], 1.0f);
        rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(world, &context, &rh);
        const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        ASSERT_TRUE(sameAnswer(hit, rh.ray.tfar, ref[k].hit, kScale * ref[k].t, 1e-3 * kScale)) << rayText(texelRays[k]);
        if (!hit) continue;
        ++hits;
        EXPECT_EQ(rh.hit.instID[0], instanceID);
        EXPECT_EQ(rh.hit.geomID, geometry->geomID());
    }
    EXPECT_GT(hits, size_t(1000));
    geometry.reset();  // detaches before the scenes go
    rtcReleaseScene(world);
    rtcReleaseScene(local);
    rtcReleaseDevice(device);
}

// A conservative technique behind the same geometry never reports a hit past exact's.
TEST(EmbreeUserGeometry, ConeNeverHitsPastExact) {
    size_t hits = 0;
    for (const MapUnderTest& map : mapsUnderTest()) {
        if (map.surface->width() > 200) continue;  // the cone maps of the 400² DEM take long to build
        const Scenes exact(map.surface, "exact"), cone(map.surface, "cone");
        testing::RaySets sets(*map.surface, 21);
        const std::vector<Ray> batch = sets.all(4000);
        const std::vector<Segment> segments = segmentsOf(batch, {}, false, 1);
        const auto e = intersectAll<16>(exact.user(), segments);
        for (const auto& c : {intersectAll<1>(cone.user(), segments), intersectAll<16>(cone.user(), segments)})
            for (size_t k = 0; k < segments.size(); ++k) {
                if (!c[k].hit) continue;
                ++hits;
                ASSERT_TRUE(e[k].hit) << map.label << " " << rayText(batch[k]);
                ASSERT_LE(c[k].t, e[k].t + std::max(1e-4f, 4 * FLT_EPSILON * e[k].t))
                    << map.label << " " << rayText(batch[k]);
            }
    }
    EXPECT_GT(hits, size_t(1000));
}

// The device's memory monitor sees the triangle scene's buffers and BVH (at least the vertex and
// index buffers), and the user geometry's scene is a small fixed cost, not per texel.
TEST(EmbreeUserGeometry, MemoryMonitorCountsTheScenes) {
    const auto surface = surfaceOf(*generateHeightfield("fbm", 128, 128, 1));
    auto triangles = EmbreeScene::create(*surface);
    ASSERT_TRUE(triangles.ok());
    const auto mesh = buildSolidMesh(*surface);
    EXPECT_GE((*triangles)->embreeBytes(), int64_t(mesh.vertices.size() * 12 + mesh.triangles.size() * 12));
    auto exact = createTracer("exact", surface);
    ASSERT_TRUE(exact.ok());
    auto user = EmbreeScene::createUserGeometry(surface, std::shared_ptr<const Tracer>(std::move(*exact)));
    ASSERT_TRUE(user.ok()) << user.error().message;
    EXPECT_GT((*user)->embreeBytes(), 0);
    EXPECT_LT((*user)->embreeBytes(), (*triangles)->embreeBytes() / 10);
    // The scene traces like any other: one ray straight down hits the top.
    std::vector<Hit> hits(1);
    (*user)->intersect1(std::vector<Ray>{Ray{vec3(64.0f, 64.0f, 100.0f), vec3(0, 0, -1), kInf}}, hits);
    EXPECT_TRUE(hits[0].hit);
}

TEST(EmbreeUserGeometry, RefusesWhatItCannotTrace) {
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("fbm", 16, 16, 1));
    auto repeat = std::make_shared<const Surface>(hf, 2.0f, EdgeMode::Repeat);
    auto clamp = std::make_shared<const Surface>(hf, 2.0f, EdgeMode::Clamp);
    auto tiled = embree::attachHeightfield(scene, repeat);
    ASSERT_FALSE(tiled.ok());
    EXPECT_EQ(tiled.error().kind, ErrorKind::Unsupported);
    auto unknown = embree::attachHeightfield(scene, clamp, "no-such-technique");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("no-such-technique"), std::string::npos);
    auto badParam = embree::attachHeightfield(scene, clamp, "cone", {{"no-such-param", 1.0}});
    EXPECT_FALSE(badParam.ok());
    EXPECT_FALSE(embree::attachHeightfield(nullptr, clamp).ok());
    EXPECT_FALSE(embree::attachTracer(scene, clamp, nullptr).ok());
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}

// The handle owns what the callbacks read: destroying it detaches the geometry; the scene, with
// the surface released by the caller, keeps working until then.
TEST(EmbreeUserGeometry, HandleOwnsTheSurfaceAndDetaches) {
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    const Segment down{Ray{vec3(8.0f, 8.0f, 50.0f), vec3(0, 0, -1), kInf}, 0.0f};
    {
        auto geometry = embree::attachHeightfield(scene, surfaceOf(*generateHeightfield("peaks6", 16, 16, 1)));
        ASSERT_TRUE(geometry.ok()) << geometry.error().message;
        embree::HeightfieldGeometry moved = std::move(*geometry);
        rtcCommitScene(scene);
        EXPECT_TRUE(intersectAll<1>(scene, {down})[0].hit);
        EXPECT_TRUE(occludedAll<16>(scene, {down})[0]);
    }
    rtcCommitScene(scene);
    EXPECT_FALSE(intersectAll<1>(scene, {down})[0].hit);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}

}  // namespace
}  // namespace relief
