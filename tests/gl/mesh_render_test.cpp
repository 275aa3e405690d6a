// The mesh preview (src/relief/preview/, `relief render --mesh`): the built-in meshes' geometry
// and tangent frames, glTF loading and its errors, every built-in mesh drawn with two rows
// (size, colours, coverage), the pixel-depth-offset crossing against the exact reference on the
// same pixels' rays, and the CLI's errors (exit codes, nothing written).
#include <relief/core/generators.h>
#include <relief/io/heightfield_io.h>
#include <relief/preview/mesh_renderer.h>
#include <relief/techniques/registry.h>
#include <support/cli_case.h>
#include <support/gl_test_support.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace relief::preview {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("relief_mesh_render_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// A quad in the xz plane as glTF, its buffer inline (base64): positions, uvs, tangents (used when
// withTangents) and indices; no normals (computed on loading from the triangles).
std::string quadGltf(bool withTangents) {
    return fmt::format(
        R"({{
  "asset": {{"version": "2.0"}},
  "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "translation": [5, 0, 0]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1{}}}, "indices": 3}}]}}],
  "buffers": [{{"byteLength": 156, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                  {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 80, "byteLength": 64}},
                  {{"buffer": 0, "byteOffset": 144, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 0, 1]}},
                {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC4"}},
                {{"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}}]
}})",
        withTangents ? R"(, "TANGENT": 2)" : "",
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/AACAPwAAAAAAAIA/AAAAAAAAgD8AAIA/"
        "AACAPwAAAAAAAAAAAACAPwAAAACamRk/AAAAAM3MTD8AAIC/mpkZPwAAAADNzEw/"
        "AACAv5qZGT8AAAAAzcxMPwAAgL+amRk/AAAAAM3MTD8AAIC/AAABAAIAAgABAAMA");
}

void expectWellFormed(const Mesh& mesh, const std::string& name, bool closed) {
    ASSERT_FALSE(mesh.indices.empty()) << name;
    EXPECT_EQ(mesh.indices.size() % 3, 0u) << name;
    double volume = 0.0;
    for (size_t k = 0; k < mesh.indices.size(); k += 3) {
        for (int c = 0; c < 3; ++c) ASSERT_LT(mesh.indices[k + c], mesh.vertices.size()) << name;
        const vec3 a = mesh.vertices[mesh.indices[k]].position,
                   b = mesh.vertices[mesh.indices[k + 1]].position,
                   c = mesh.vertices[mesh.indices[k + 2]].position;
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
        // Counter-clockwise seen from outside: the face normal agrees with the vertex normals.
        const vec3 face = glm::cross(b - a, c - a);
        if (glm::length(face) > 1e-7f) {
            const vec3 n = mesh.vertices[mesh.indices[k]].normal;
            EXPECT_GT(glm::dot(face, n), 0.0f) << name << " triangle " << k / 3;
        }
    }
    if (closed) {
        EXPECT_GT(volume, 0.5) << name << ": outward triangles enclose the volume";
    }
    for (const MeshVertex& v : mesh.vertices) {
        EXPECT_LE(glm::length(v.position), 1.0f + 1e-4f) << name;
        EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f) << name;
        EXPECT_NEAR(glm::length(vec3(v.tangent)), 1.0f, 1e-4f) << name;
        EXPECT_NEAR(glm::dot(vec3(v.tangent), v.normal), 0.0f, 1e-4f) << name;
        EXPECT_EQ(std::abs(v.tangent.w), 1.0f) << name;
        EXPECT_GT(v.uvScale.x, 0.0f) << name;
        EXPECT_GT(v.uvScale.y, 0.0f) << name;
    }
}

TEST(MeshPreview, BuiltinMeshesAreClosedAndFramed) {
    for (std::string_view name : kBuiltinMeshes) {
        auto mesh = builtinMesh(name);
        ASSERT_TRUE(mesh) << mesh.error().message;
        expectWellFormed(*mesh, std::string(name), name != "plane");
    }
    // The plane's frame: u along +x, v down the image (-y), so a top view reads like the image.
    const Mesh plane = *builtinMesh("plane");
    for (const MeshVertex& v : plane.vertices) {
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, -1.0f);
        EXPECT_NEAR(v.uvScale.x, std::sqrt(2.0f), 1e-5f);  // side 2/sqrt(2) after normalizing
    }
    auto unknown = builtinMesh("torus");
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().kind, ErrorKind::BadArgument);
    EXPECT_NE(unknown.error().message.find("plane, cube, sphere, cylinder"), std::string::npos);
}

TEST(MeshPreview, GltfLoadsAndBadFilesAreErrors) {
    const fs::path dir = freshDir("gltf");
    std::ofstream(dir / "quad.gltf") << quadGltf(false);
    auto quad = loadMesh((dir / "quad.gltf").string());
    ASSERT_TRUE(quad) << quad.error().message;
    EXPECT_EQ(quad->vertices.size(), 4u);
    EXPECT_EQ(quad->indices.size(), 6u);
    expectWellFormed(*quad, "quad.gltf", false);
    for (const MeshVertex& v : quad->vertices) {
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-5f);  // +u along +x (computed from the UVs)
        EXPECT_NEAR(v.position.x * v.position.x + v.position.z * v.position.z, 1.0f, 1e-4f);
    }

    // Tangents from the file are kept (here along (0.6, 0, 0.8), left-handed).
    std::ofstream(dir / "tangents.gltf") << quadGltf(true);
    auto given = loadMesh((dir / "tangents.gltf").string());
    ASSERT_TRUE(given) << given.error().message;
    for (const MeshVertex& v : given->vertices) {
        EXPECT_NEAR(v.tangent.x, 0.6f, 1e-5f);
        EXPECT_NEAR(v.tangent.z, 0.8f, 1e-5f);
        EXPECT_EQ(v.tangent.w, -1.0f);
    }

    auto missing = loadMesh((dir / "none.gltf").string());
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().kind, ErrorKind::Io);
    std::ofstream(dir / "bad.gltf") << "{ not json";
    auto bad = loadMesh((dir / "bad.gltf").string());
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().kind, ErrorKind::InvalidInput);
    EXPECT_NE(bad.error().message.find("bad.gltf"), std::string::npos);
    // An index accessor that runs past its buffer.
    std::string past = quadGltf(false);
    past.replace(past.find(R"("count": 6)"), 10, R"("count": 600)");
    std::ofstream(dir / "past.gltf") << past;
    auto overrun = loadMesh((dir / "past.gltf").string());
    ASSERT_FALSE(overrun);
    EXPECT_EQ(overrun.error().kind, ErrorKind::InvalidInput);
    std::ofstream(dir / "empty.gltf") << R"({"asset": {"version": "2.0"}})";
    auto empty = loadMesh((dir / "empty.gltf").string());
    ASSERT_FALSE(empty);
    EXPECT_EQ(empty.error().kind, ErrorKind::InvalidInput);
    fs::remove_all(dir);
}

struct Scene {
    std::shared_ptr<const Surface> surface;
    TechniqueMaps maps;
    ParamValues params;
};

Scene sceneFor(const TechniqueInfo& info, std::shared_ptr<const Surface> surface) {
    Scene s{surface, {}, *resolveParams(info, {})};
    if (info.buildMaps) {
        auto built = info.buildMaps(TechniqueInput{surface, s.params});
        EXPECT_TRUE(built) << built.error().message;
        if (built) s.maps = std::move(*built);
    }
    return s;
}

TEST(MeshPreview, EveryBuiltinMeshWithTwoRows) {
    RELIEF_REQUIRE_GL();
    auto hf = generateHeightfield("bricks", 64, 64, 1);
    ASSERT_TRUE(hf) << hf.error().message;
    auto surface = std::make_shared<const Surface>(
        std::make_shared<const Heightfield>(std::move(*hf)), 6.0f, EdgeMode::Repeat);
    auto color = loadGeneratorColor("gen:bricks:64x64");
    ASSERT_TRUE(color) << color.error().message;
    MeshRenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    settings.tiles = 2.0f;
    settings.view.elevationDeg = 30.0f;
    for (const char* row : {"cone", "linear"}) {
        const TechniqueInfo& info = **lookupTechnique(row);
        const Scene scene = sceneFor(info, surface);
        for (std::string_view name : kBuiltinMeshes) {
            SCOPED_TRACE(fmt::format("{} on {}", row, name));
            const Mesh mesh = *builtinMesh(name);
            auto image =
                renderMesh(info, scene.params, scene.maps, surface, mesh, &*color, settings);
            ASSERT_TRUE(image) << image.error().message;
            EXPECT_EQ(image->color.width, 96);
            EXPECT_EQ(image->color.height, 72);
            int covered = 0;
            Rgb8 lo(255), hi(0);
            for (size_t k = 0; k < image->color.pixels.size(); ++k) {
                const bool relief = image->object.pixels[k] == MeshPixel::Relief;
                EXPECT_NE(image->object.pixels[k], MeshPixel::Crossing);
                EXPECT_EQ(relief, std::isfinite(image->distance.pixels[k]));
                if (!relief) continue;
                ++covered;
                lo = glm::min(lo, image->color.pixels[k]);
                hi = glm::max(hi, image->color.pixels[k]);
            }
            // The mesh fills a fair part of the frame, not all of it; the bricks' red and the
            // mortar's grey and the shading make a spread of colours.
            const double coverage = double(covered) / double(96 * 72);
            EXPECT_GT(coverage, name == "plane" ? 0.12 : 0.2);
            EXPECT_LT(coverage, 0.9);
            EXPECT_GT(int(hi.x) - int(lo.x), 60);
            EXPECT_GT(int(hi.y) - int(lo.y), 30);
            // The corners show the background.
            EXPECT_EQ(image->object.at(0, 0), MeshPixel::Background);
            EXPECT_EQ(image->color.at(0, 0), image->color.at(95, 71));
        }
    }
}

// Clamp mode: a ray that leaves the map's uv square is discarded (a silhouette), so the plane seen
// at a grazing angle covers less than the same view in repeat mode, where every ray hits.
TEST(MeshPreview, ClampedMapsHaveSilhouettes) {
    RELIEF_REQUIRE_GL();
    const TechniqueInfo& info = **lookupTechnique("cone");
    MeshRenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    settings.view.elevationDeg = 20.0f;
    int covered[2] = {};
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        auto surface = testing::generatedSurface("fbm", 48, 48, 0.25f, edge, 3);
        ASSERT_TRUE(surface);
        const Scene scene = sceneFor(info, surface);
        auto image = renderMesh(info, scene.params, scene.maps, surface, *builtinMesh("plane"),
                                nullptr, settings);
        ASSERT_TRUE(image) << image.error().message;
        for (MeshPixel p : image->object.pixels)
            covered[int(edge == EdgeMode::Repeat)] += p == MeshPixel::Relief;
    }
    EXPECT_LT(covered[0], covered[1]);
    EXPECT_GT(covered[0], covered[1] / 2);
}

// The crossing square against the relief: per pixel, which one the exact reference puts in front
// on the pixel's own ray (the plane mesh: its tangent frame is one affine map world -> texel).
TEST(MeshPreview, DepthOffsetCrossingMatchesTheReference) {
    RELIEF_REQUIRE_GL();
    auto surface = testing::generatedSurface("fbm", 64, 64, 0.2f, EdgeMode::Clamp, 7);
    ASSERT_TRUE(surface);
    const TechniqueInfo& info = **lookupTechnique("cone");
    const Scene scene = sceneFor(info, surface);
    const Mesh mesh = *builtinMesh("plane");
    MeshRenderSettings settings;
    settings.width = 120;
    settings.height = 90;
    settings.view.elevationDeg = 35.0f;
    settings.view.distance = 0.9f;
    settings.crossingHeight = 0.5f;
    auto image = renderMesh(info, scene.params, scene.maps, surface, mesh, nullptr, settings);
    ASSERT_TRUE(image) << image.error().message;

    // world -> texel: x = W·(u0 + (p - p0)·t / su), y = H·(v0 + (p - p0)·b / sv),
    // z = D + W·(p - p0)·n / su (the mesh is the relief's top).
    const MeshVertex& v0 = mesh.vertices[0];
    const vec3 t = vec3(v0.tangent), n = v0.normal, b = v0.tangent.w * glm::cross(n, t);
    const float W = float(surface->width()), H = float(surface->height());
    auto texelOf = [&](vec3 p, float w) {  // w = 1: a point, 0: a direction
        const vec3 d = p - w * v0.position;
        return vec3(W * (w * v0.uv.x + glm::dot(d, t) / v0.uvScale.x),
                    H * (w * v0.uv.y + glm::dot(d, b) / v0.uvScale.y),
                    w * surface->depth() + W * glm::dot(d, n) / v0.uvScale.x);
    };
    const Camera camera = meshCamera(settings);
    const float zCross = crossingZ(mesh, *surface, settings);
    std::vector<Ray> rays;
    std::vector<vec3> worldDirs;
    for (int y = 0; y < settings.height; ++y)
        for (int x = 0; x < settings.width; ++x) {
            const Ray world = camera.primaryRay(float(x) + 0.5f, float(y) + 0.5f);
            worldDirs.push_back(world.direction);
            rays.push_back(Ray{texelOf(world.origin, 1.0f),
                               glm::normalize(texelOf(world.direction, 0.0f)), kInfinity});
        }
    auto exact = createTracer(referenceTechnique().name, surface);
    ASSERT_TRUE(exact) << exact.error().message;
    std::vector<Hit> hits(rays.size());
    traceAll(**exact, rays, hits);
    Image<MeshPixel> expected(settings.width, settings.height);
    for (size_t k = 0; k < rays.size(); ++k) {
        const vec3 dir = worldDirs[k];
        float crossing = dir.z < 0.0f ? (zCross - camera.eye().z) / dir.z : kInfinity;
        const vec3 atCrossing = camera.eye() + crossing * dir;
        if (std::max(std::abs(atCrossing.x), std::abs(atCrossing.y)) > 1.2f) crossing = kInfinity;
        // The texel map is affine: a hit at texel distance t is t / |A·dir| along the world ray.
        // The relief shows only where the ray crosses the mesh (the box's top face): the
        // rasterizer has no fragment where it would enter the box through a side.
        const Ray& r = rays[k];
        const vec3 top = r.origin + ((surface->depth() - r.origin.z) / r.direction.z) * r.direction;
        const bool throughMesh =
            r.direction.z < 0.0f && top.x >= 0.0f && top.x <= W && top.y >= 0.0f && top.y <= H;
        const float relief =
            hits[k].hit && throughMesh ? hits[k].t / glm::length(texelOf(dir, 0.0f)) : kInfinity;
        expected.pixels[k] = crossing < relief    ? MeshPixel::Crossing
                             : relief < kInfinity ? MeshPixel::Relief
                                                  : MeshPixel::Background;
    }
    size_t counts[3] = {}, differ = 0, far = 0;
    for (int y = 0; y < settings.height; ++y)
        for (int x = 0; x < settings.width; ++x) {
            const MeshPixel got = image->object.at(x, y);
            ++counts[int(got)];
            if (got == expected.at(x, y)) continue;
            ++differ;
            // Within 1 px of where the reference puts the same thing.
            bool near = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    near |= xx >= 0 && yy >= 0 && xx < settings.width && yy < settings.height &&
                            expected.at(xx, yy) == got;
                }
            if (!near) {
                ++far;
                std::printf("  pixel (%d, %d): gpu %d, reference %d\n", x, y, int(got),
                            int(expected.at(x, y)));
            }
        }
    std::printf(
        "crossing: relief %zu px, crossing %zu px, background %zu px; %zu differ from the "
        "reference, %zu of them more than 1 px from it\n",
        counts[1], counts[2], counts[0], differ, far);
    // Both show in good numbers (the square lies below the mesh: only the depth offset shows it).
    EXPECT_GT(counts[1], size_t(settings.width * settings.height / 10));
    EXPECT_GT(counts[2], size_t(settings.width * settings.height / 10));
    EXPECT_EQ(far, 0u);
    EXPECT_LT(differ, size_t(settings.width * settings.height / 50));
}

TEST(MeshPreview, CliErrorsWriteNothing) {
    RELIEF_REQUIRE_GL();
    const fs::path dir = freshDir("cli");
    std::ofstream(dir / "bad.gltf") << "{ not json";
    const std::string common = "render gen:bricks:32x32 -t cone --size 48x32 -o {tmp}/out.png ";
    const testing::CliCase cases[] = {
        {"unknown mesh", common + "--mesh torus", 1, "", "--mesh 'torus'"},
        {"missing file", common + "--mesh {tmp}/none.gltf", 2, "", "none.gltf"},
        {"bad glTF", common + "--mesh {tmp}/bad.gltf", 3, "", "not a valid glTF"},
        {"no shader function", "render gen:bricks:32x32 -t exact --mesh cube -o {tmp}/out.png", 5,
         "", "no shader-library function"},
        {"mesh-only option", common + "--tiles 2", 1, "", "--tiles: read with --mesh only"},
        {"one technique", "render gen:bricks:32x32 -t cone,linear --mesh cube -o {tmp}/out.png", 1,
         "", "--mesh draws one technique"},
        {"not for meshes", common + "--mesh cube --steps-out {tmp}/s.png", 1, "",
         "--steps-out: not read with --mesh"},
    };
    for (const testing::CliCase& c : cases) {
        testing::runCliCase(c, dir);
        EXPECT_FALSE(fs::exists(dir / "out.png")) << c.name;
    }
    const testing::CliCase ok = {"cube",
                                 common +
                                     "--mesh cube --crossing-plane 0.5 --color gen "
                                     "--shadows --edge repeat --tiles 2 "
                                     "--depth-out {tmp}/depth.pfm",
                                 0, "cone on mesh cube: 48x32", ""};
    testing::runCliCase(ok, dir);
    EXPECT_TRUE(fs::exists(dir / "out.png"));
    EXPECT_TRUE(fs::exists(dir / "depth.pfm"));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace relief::preview
