#include <relief/surface/texel_boxes.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace relief {

namespace {

// t where the ray crosses the texel edge x = edge (the pyramid walk's boundaryT on texels).
float edgeT(int edge, float origin, float inverse) { return (float(edge) - origin) * inverse; }

float exitT(int texel, int step, float origin, float inverse) {
    return step == 0 ? kInfinity : edgeT(step > 0 ? texel + 1 : texel, origin, inverse);
}

}  // namespace

Hit firstTexelBoxHit(const Surface& s, const Ray& ray) {
    Hit hit;
    const RayInterval span = s.clip(ray);
    if (span.empty()) return hit;
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    const float invX = 1.0f / d.x, invY = 1.0f / d.y, invZ = 1.0f / d.z;
    const int stepX = d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0);
    const int stepY = d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0);
    const bool repeat = s.edge() == EdgeMode::Repeat;
    const vec3 entry = ray.at(span.tEnter);
    int i = int(std::floor(entry.x)), j = int(std::floor(entry.y));
    if (!repeat) {
        i = std::clamp(i, 0, s.width() - 1);
        j = std::clamp(j, 0, s.height() - 1);
    }
    const float zTolerance = floorTolerance(o.z, s.depth());
    if (o.z + span.tEnter * d.z <= zTolerance) {  // entering through the floor (from below)
        hit.hit = true;
        hit.t = span.tEnter;
        hit.position = entry;
        return hit;
    }
    float t = span.tEnter;
    float exitX = exitT(i, stepX, o.x, invX), exitY = exitT(j, stepY, o.y, invY);
    for (;;) {
        ++hit.steps;
        ++hit.fetches;
        const float tOut = std::max(t, std::min({exitX, exitY, span.tExit}));
        const float tHit = enterBelow(s.sampleZ(i, j), o, d, invZ, t, tOut);
        if (tHit <= tOut) {
            hit.hit = true;
            hit.t = tHit;
            hit.position = ray.at(tHit);
            return hit;
        }
        if (tOut >= span.tExit) break;
        t = tOut;
        if (exitX <= exitY) {
            i += stepX;
            if (!repeat && (i < 0 || i >= s.width())) break;
            exitX = exitT(i, stepX, o.x, invX);
        } else {
            j += stepY;
            if (!repeat && (j < 0 || j >= s.height())) break;
            exitY = exitT(j, stepY, o.y, invY);
        }
    }
    // Leaving through the floor (the rule of the S reference too).
    if (d.z < 0.0f && o.z + span.tExit * d.z <= zTolerance) {
        hit.hit = true;
        hit.t = span.tExit;
        hit.position = ray.at(span.tExit);
    }
    return hit;
}

TexelBoxMesh texelBoxMesh(const Surface& s) {
    TexelBoxMesh mesh;
    const auto quad = [&](vec3 a, vec3 b, vec3 c, vec3 e) {
        const unsigned k = unsigned(mesh.vertices.size());
        mesh.vertices.insert(mesh.vertices.end(), {a, b, c, e});
        mesh.triangles.push_back({k, k + 1, k + 2});
        mesh.triangles.push_back({k, k + 2, k + 3});
    };
    const int w = s.width(), h = s.height();
    // The floor: rays from below the box meet the solid there (the S mesh has it too).
    const float fw = float(w), fh = float(h);
    quad({0.0f, 0.0f, 0.0f}, {0.0f, fh, 0.0f}, {fw, fh, 0.0f}, {fw, 0.0f, 0.0f});
    const auto z = [&](int i, int j) {  // 0 outside the map: the outer walls go to the floor
        return i < 0 || j < 0 || i >= w || j >= h ? 0.0f : s.sampleZ(i, j);
    };
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const float x0 = float(i), x1 = float(i + 1), y0 = float(j), y1 = float(j + 1);
            const float top = z(i, j);
            quad({x0, y0, top}, {x1, y0, top}, {x1, y1, top}, {x0, y1, top});
            // The walls on the low side of this texel along x and y (x = i, y = j); the last
            // column's and row's high side below.
            for (int axis = 0; axis < 2; ++axis) {
                for (int side = 0; side < (axis == 0 ? (i == w - 1 ? 2 : 1) : (j == h - 1 ? 2 : 1));
                     ++side) {
                    const float a = axis == 0 ? z(i + side - 1, j) : z(i, j + side - 1);
                    const float b = axis == 0 ? z(i + side, j) : z(i, j + side);
                    if (a == b) continue;
                    const float lo = std::min(a, b), hi = std::max(a, b);
                    if (axis == 0) {
                        const float x = float(i + side);
                        quad({x, y0, lo}, {x, y1, lo}, {x, y1, hi}, {x, y0, hi});
                    } else {
                        const float y = float(j + side);
                        quad({x0, y, lo}, {x1, y, lo}, {x1, y, hi}, {x0, y, hi});
                    }
                }
            }
        }
    return mesh;
}

}  // namespace relief
