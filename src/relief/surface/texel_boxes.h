#pragma once
// texel boxes — the quadtree paper's surface (Schroders & van Gulik 2006 §3: "each texel is a
//   box" of the sample's height), offered by `quadtree` and `maxmip` as box-surface = 2.
// Texel (i, j) is the solid box [i, i+1] × [j, j+1] × [0, D·h(i, j)]: DESIGN §1 puts sample
//   (i, j) at (i+0.5, j+0.5), so the box is the sample's footprint, centred on it (the paper's
//   placement: a texture's texel). Clamp: the W×H boxes fill the relief's box exactly (its side
//   walls below the boxes are hit at the entry, as for S); repeat: they tile the plane.
// firstTexelBoxHit is the exact first hit on that surface: a walk over the texels the ray crosses
//   (Amanatides–Woo with edges at integers, t from boundaryT's formula); in each texel the ray
//   meets the box at the start of its segment (a wall, or below the top at the entry) or where
//   it crosses the top. Validated by brute force and by Embree on texelBoxMesh (its test).
//   A ray through a texel corner (both edges at the same t) crosses the x edge first, as if
//   nudged against its y direction: of the two texels beside the corner it meets the one
//   beyond the x edge (a consistent tie rule; the walks and the brute-force test keep it),
//   except at the point where the ray leaves the relief's box, where the walk has ended.
#include <relief/core/math.h>
#include <relief/surface/surface.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace relief {

// Steps = texels visited; fetches = one height per texel.
Hit firstTexelBoxHit(const Surface& s, const Ray& ray);

// The boxes' faces as triangles (clamp): tops, the walls between neighbours of different
// heights, the outer walls and the floor (the closed solid); for the Embree peer.
struct TexelBoxMesh {
    std::vector<vec3> vertices;
    std::vector<glm::uvec3> triangles;
};
TexelBoxMesh texelBoxMesh(const Surface& s);

// A ray's z at or below this counts as on the floor z = 0 (the float rounding of o.z + t·d.z):
// entering or leaving the box there is a hit, the floor being part of the solid, even over a
// box of height zero that rounding leaves a hair above.
inline float floorTolerance(float originZ, float depth) {
    return 4.0f * std::numeric_limits<float>::epsilon() * (std::abs(originZ) + depth);
}

// First t in [t, tOut] where the ray is at or below height `top` (descending: where it crosses
// it, clamped to the segment), or kInfinity: the box test of one texel column.
inline float enterBelow(float top, const vec3& o, const vec3& d, float invZ, float t, float tOut) {
    if (d.z < 0.0f) {
        if (o.z + tOut * d.z > top) return kInfinity;
        return std::clamp((top - o.z) * invZ, t, tOut);
    }
    return o.z + t * d.z <= top ? t : kInfinity;
}

}  // namespace relief
