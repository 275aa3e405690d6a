#pragma once
// The material preview on a mesh (issue 19): the mesh rasterized through the GL backend's EGL
// context, its fragment shader calling the engine shader library's function of one registry row
// (shaders/relief/) in the mesh's tangent frame: the hit's uv shades the pixel (mipmapped sRGB
// colour map, a normal map made from the heights, diffuse + highlight), the row's Shadow function
// darkens it toward the light, gl_FragDepth moves it to the hit (pixel depth offset, so other
// geometry crosses the relief where the relief is), and a ray that leaves the UV domain of a
// clamped map is discarded (silhouettes). Optional: a flat horizontal square crossing the relief.
//
// Used by `relief render --mesh` (headless) and meant for the viewer and the web page's reference.
#include <relief/core/error.h>
#include <relief/core/image.h>
#include <relief/io/map_file.h>
#include <relief/preview/mesh.h>
#include <relief/render/camera.h>
#include <relief/surface/surface.h>
#include <relief/techniques/technique.h>

#include <memory>
#include <optional>

namespace relief::preview {

struct MeshRenderSettings {
    int width = 800, height = 600;
    OrbitView view;  // around the origin, distance in mesh diameters (2 units)
    vec3 towardsLight = vec3(0, 0, 1);
    bool shadows = true;     // the row's Shadow function toward the light
    float tiles = 1.0f;      // uv scale: the map repeats this often across a face
    float midLevel = 1.0f;   // ReliefParams::midLevel: 1 = the mesh is the relief's top
    float exposure = 0.0f;   // stops
    float specular = 0.25f;  // strength of the highlight
    // A horizontal square (side 2.4 mesh units) through the mesh's top point lowered by
    // (midLevel − h) × the relief's depth (h in [0, 1], 0 = the relief's bottom): it cuts the
    // relief of the topmost face.
    std::optional<float> crossingHeight;
};

// What the crossing square's z is for `mesh` (crossingHeight h, the relief depth in world units).
float crossingZ(const Mesh& mesh, const Surface& surface, const MeshRenderSettings& settings);

// The relief's depth in world units on `mesh` (D / W × the mean |dP/du| ÷ tiles).
float worldDepth(const Mesh& mesh, const Surface& surface, float tiles);

enum class MeshPixel : uint8_t { Background = 0, Relief = 1, Crossing = 2 };

struct MeshImage {
    ImageRgb8 color;          // sRGB encoded
    ImageF distance;          // from the eye to what the pixel shows (mesh units), +inf: nothing
    Image<MeshPixel> object;  // what the pixel shows
};

// The camera of a render (primaryRay(px + 0.5, py + 0.5) is pixel (px, py)'s ray, row 0 at the
// top, the ray the rasterizer uses).
Camera meshCamera(const MeshRenderSettings& settings);

// The GL side of the preview, for a caller with its own framebuffer (the viewer): the row's
// program and textures, made once; setMesh uploads a mesh; draw draws it (and the crossing square)
// into the bound framebuffer with depth testing, colour to draw buffer 0 (sRGB encoded) and
// (distance, MeshPixel, steps) to draw buffer 1 when there is one. The viewport's aspect must be
// the camera's. A GL context (an EglContext::Scope, or the window's) must be current throughout.
class MeshPreview {
  public:
    static Result<MeshPreview> create(const TechniqueInfo& info, const ParamValues& params,
                                      const TechniqueMaps& maps,
                                      std::shared_ptr<const Surface> surface,
                                      const ImageRgb8* color);
    ~MeshPreview();
    MeshPreview(MeshPreview&&) noexcept;
    MeshPreview& operator=(MeshPreview&&) noexcept;

    void setMesh(const Mesh& mesh);
    void draw(const Camera& camera, const MeshRenderSettings& settings) const;

  private:
    struct State;
    explicit MeshPreview(std::unique_ptr<State> state);
    std::unique_ptr<State> m_state;
};

// Renders `mesh` with the row `info` (its shaderFunction; parameters resolved, maps built or
// baked for `surface`) offscreen through the shared EGL context and reads it back. `color`: sRGB
// colour map (null: a neutral grey). Unsupported for a row without a shader function, Runtime
// for GL.
Result<MeshImage> renderMesh(const TechniqueInfo& info, const ParamValues& params,
                             const TechniqueMaps& maps, std::shared_ptr<const Surface> surface,
                             const Mesh& mesh, const ImageRgb8* color,
                             const MeshRenderSettings& settings);

}  // namespace relief::preview
