// relief shader library: the conventions every technique file shares (docs/engine.md).
// Include this file, then one technique file; the including shader sets #version (330 core,
// 300 es, or 450 for Vulkan, where it also gives the samplers their set/binding). Textures are
// read with texelFetch only (nearest, no filtering, no mipmaps needed): heights as R32F (or any
// UNORM format) holding h in [0, 1], maps as the bake's arrays, one texture per array.
//
// Engine side: uv in [0, 1]², a view direction in tangent space (x along +u, y along +v, z out
// of the surface, pointing from the surface toward the eye), ReliefParams. Inside: relief's
// texel space (DESIGN §1): x = u·W, y = v·H, z = D·h, one unit = one texel; the tracers are the
// C++ tracers (src/relief/techniques/*/*.h) step for step, on textures instead of buffers.
// Departure from the C++: plain float arithmetic (no `precise`, no fp64), so a result may differ
// from the CPU's by float rounding (relief's GL tests bound it).

#ifdef GL_ES
precision highp float;
precision highp int;
precision highp sampler2D;
#endif

const int kReliefClamp = 0;   // the box [0,W]×[0,H]: nothing outside it (DESIGN §1)
const int kReliefRepeat = 1;  // tiling: the maps were baked with wrap-around
const float kReliefInfinity = 3.0e38;
const float kReliefFloatEpsilon = 1.1920929e-7;
const float kReliefRepeatTravel = 8.0;  // Surface::kRepeatTravelFactor: tiles a ray may cross
const float kReliefShadowBias = 1.0e-3;  // texels above the hit where a shadow ray starts

struct ReliefParams {
    vec2 mapSize;     // W, H: the heightfield's size in texels (the maps' size)
    float depth;      // D: relief depth in texels, the depth the maps were baked with
    float midLevel;   // height h (0..1) at which the mesh surface lies: 1 = top (classic POM)
    int edge;         // kReliefClamp or kReliefRepeat, as baked
    int maxSteps;     // iteration cap (relief's max-steps)
    int binarySteps;  // refinement steps (linear, relaxed-cone: relief's binary-steps)
    int bits;         // cone maps, max pyramids: 32 = floats, 16 / 8 = codes (the map's "bits")
    int sqrtRatio;    // cone maps: 1 when codes hold sqrt(c / cMax) (the map's "sqrt")
    float coneMax;    // cone maps: cMax (the map's "cone-max")
    int ascend;       // quadtree: 1 = up one level on entering a new parent (relief's default)
    float maxZ;       // qdm: D × the highest height of the map (Surface::maxZ)
    float maxDistance;  // qdm: the map's "max-distance" (0 = unlimited)
    float phiMax;         // safety-*: the map's "phi-max" (degrees; 90 = no restriction)
    int exterior;         // safety-*: the map's "exterior" (1 = maps for exterior rays only)
    int viewDependent;    // safety-*: 1 = S linear between test positions (§7, approximate)
    int positiveDistance; // safety-*: 1 = distances clamped to >= 1 (§7, approximate)
    int isotropic;        // safety-sd: 1 = the "sd" map has one channel for every ray class
    int variant;          // qdm: the map's "variant" (1 = the paper's map and Algorithm 1)
};

// relief's defaults for a W×H map baked at depth D (texels), clamp mode, mesh at the top.
ReliefParams reliefParams(vec2 mapSize, float depth) {
    return ReliefParams(mapSize, depth, 1.0, kReliefClamp, 64, 8, 32, 0, 1.0, 1, depth, 0.0, 90.0,
                        0, 0, 0, 0, 0);
}

// Where the view ray meets the relief.
struct ReliefHit {
    bool hit;       // false: the ray leaves the relief (a silhouette in clamp mode)
    vec2 uv;        // of the hit (not wrapped in repeat mode: continuous for derivatives)
    float depth;    // below the mesh surface along its normal, in u units: (D·mid − z) / W;
                    // depth / normalize(viewDir).z is the distance along the view ray (PDO)
    vec3 position;  // the hit in texel space (x, y, z = D·h)
    int steps;      // iterations of the technique's main loop
};

// A ray in texel space: origin + t·direction, direction normalized.
struct ReliefRay {
    vec3 origin;
    vec3 direction;
};

// Conversions at the boundary.
vec2 reliefTexelFromUv(vec2 uv, ReliefParams p) { return uv * p.mapSize; }
vec2 reliefUvFromTexel(vec2 texel, ReliefParams p) { return texel / p.mapSize; }
float reliefZFromHeight(float h, ReliefParams p) { return p.depth * h; }
float reliefHeightFromZ(float z, ReliefParams p) { return z / p.depth; }
// An engine's height scale s (relief depth as a fraction of the u extent) in texels.
float reliefDepthFromScale(float heightScale, vec2 mapSize) { return heightScale * mapSize.x; }
// A tangent-space direction (u units on x and z, v units on y) in texel space, normalized.
vec3 reliefTexelDirection(vec3 tangentDir, ReliefParams p) {
    return normalize(vec3(tangentDir.x * p.mapSize.x, tangentDir.y * p.mapSize.y,
                          tangentDir.z * p.mapSize.x));
}

// The view ray of a fragment: from the mesh surface point (u·W, v·H, D·mid) away from the eye,
// backed up to the top of the box (z = D) when the mesh lies below it (mid < 1).
ReliefRay reliefViewRay(vec2 uv, vec3 viewDirTangent, ReliefParams p) {
    vec3 d = -reliefTexelDirection(viewDirTangent, p);
    vec3 o = vec3(reliefTexelFromUv(uv, p), p.depth * p.midLevel);
    if (p.midLevel < 1.0 && d.z < 0.0) o -= d * ((p.depth - o.z) / -d.z);
    return ReliefRay(o, d);
}

ReliefHit reliefNoHit(int steps) {
    return ReliefHit(false, vec2(0.0), 0.0, vec3(0.0), steps);
}

ReliefHit reliefHitAt(ReliefRay ray, float t, int steps, ReliefParams p) {
    vec3 q = ray.origin + t * ray.direction;
    return ReliefHit(true, reliefUvFromTexel(q.xy, p),
                     (p.depth * p.midLevel - q.z) / p.mapSize.x, q, steps);
}

// hit ? reliefHitAt(ray, t, steps, p) : reliefNoHit(steps), for GLSL ES 3.00 / WebGL, where the
// ternary operator takes no structures.
ReliefHit reliefHitIf(bool hit, ReliefRay ray, float t, int steps, ReliefParams p) {
    if (hit) return reliefHitAt(ray, t, steps, p);
    return reliefNoHit(steps);
}

// The shadow ray of a hit toward a light (tangent space, pointing to the light): from just above
// the hit. Lights at or below the surface plane give a ray with direction.z <= 0.
ReliefRay reliefShadowRay(ReliefHit hit, vec3 lightDirTangent, ReliefParams p) {
    return ReliefRay(hit.position + vec3(0.0, 0.0, kReliefShadowBias),
                     reliefTexelDirection(lightDirTangent, p));
}

// ---- The canonical surface S (relief::Surface, surface.{h,cpp}) ----

int reliefWrapIndex(int i, int n) { return i >= 0 ? i % n : n - 1 - (-1 - i) % n; }

// A sample's index in the texture: clamp mode extends the outermost samples (the half-texel
// border strips), repeat wraps.
ivec2 reliefSampleIndex(int i, int j, ReliefParams p) {
    ivec2 n = ivec2(p.mapSize);
    if (p.edge == kReliefClamp) return clamp(ivec2(i, j), ivec2(0), n - 1);
    return ivec2(reliefWrapIndex(i, n.x), reliefWrapIndex(j, n.y));
}

float reliefSampleZ(sampler2D heights, int i, int j, ReliefParams p) {
    return p.depth * texelFetch(heights, reliefSampleIndex(i, j, p), 0).r;
}

// The four corners of cell (ci, cj): z00, z10, z01, z11.
vec4 reliefCellCorners(sampler2D heights, int ci, int cj, ReliefParams p) {
    return vec4(reliefSampleZ(heights, ci, cj, p), reliefSampleZ(heights, ci + 1, cj, p),
                reliefSampleZ(heights, ci, cj + 1, p), reliefSampleZ(heights, ci + 1, cj + 1, p));
}

// The cell's two triangle planes (z0, sx, sy each) split along the lower diagonal; S is their
// maximum (planesFromCorners).
void reliefCellPlanes(vec4 c, out vec3 first, out vec3 second) {
    if (c.x + c.w <= c.y + c.z) {  // 00–11 is the lower diagonal (ties included)
        first = vec3(c.x, c.y - c.x, c.w - c.y);
        second = vec3(c.x, c.w - c.z, c.z - c.x);
    } else {
        first = vec3(c.x, c.y - c.x, c.z - c.x);
        second = vec3(c.y + c.z - c.w, c.w - c.z, c.w - c.y);
    }
}

float reliefPlaneAt(vec3 plane, float u, float v) { return plane.x + plane.y * u + plane.z * v; }

int reliefClampCellX(int ci, ReliefParams p) {
    return p.edge == kReliefClamp ? clamp(ci, -1, int(p.mapSize.x) - 1) : ci;
}
int reliefClampCellY(int cj, ReliefParams p) {
    return p.edge == kReliefClamp ? clamp(cj, -1, int(p.mapSize.y) - 1) : cj;
}

// S at (x, y): the max of the cell's planes (heightAt).
float reliefHeightAt(sampler2D heights, float x, float y, ReliefParams p) {
    int ci = reliefClampCellX(int(floor(x - 0.5)), p);
    int cj = reliefClampCellY(int(floor(y - 0.5)), p);
    vec3 first, second;
    reliefCellPlanes(reliefCellCorners(heights, ci, cj, p), first, second);
    float u = x - (float(ci) + 0.5), v = y - (float(cj) + 0.5);
    return max(reliefPlaneAt(first, u, v), reliefPlaneAt(second, u, v));
}

// Bilinear interpolation of the samples (bilinearZ): what a bilinear texture fetch gives, with
// full-precision weights.
float reliefBilinearZ(sampler2D heights, float x, float y, ReliefParams p) {
    int ci = reliefClampCellX(int(floor(x - 0.5)), p);
    int cj = reliefClampCellY(int(floor(y - 0.5)), p);
    float u = clamp(x - (float(ci) + 0.5), 0.0, 1.0), v = clamp(y - (float(cj) + 0.5), 0.0, 1.0);
    vec4 c = reliefCellCorners(heights, ci, cj, p);
    return (1.0 - v) * ((1.0 - u) * c.x + u * c.y) + v * ((1.0 - u) * c.z + u * c.w);
}

// Intersects [lo, hi] with the slab [a, b] along one axis (clipSlab).
bool reliefClipSlab(float origin, float direction, float a, float b, inout float lo,
                    inout float hi) {
    if (direction == 0.0) return origin >= a && origin <= b;
    float inv = 1.0 / direction;
    float t0 = (a - origin) * inv, t1 = (b - origin) * inv;
    lo = max(lo, min(t0, t1));
    hi = min(hi, max(t0, t1));
    return lo <= hi;
}

// The ray's interval (tEnter, tExit) inside the box (Surface::clip); empty when tEnter > tExit.
vec2 reliefClip(ReliefRay ray, ReliefParams p) {
    float lo = 0.0, hi = kReliefInfinity;
    vec3 o = ray.origin, d = ray.direction;
    bool inside = reliefClipSlab(o.z, d.z, 0.0, p.depth, lo, hi);
    if (p.edge == kReliefClamp) {
        inside = inside && reliefClipSlab(o.x, d.x, 0.0, p.mapSize.x, lo, hi) &&
                 reliefClipSlab(o.y, d.y, 0.0, p.mapSize.y, lo, hi);
    } else {
        float horizontal = sqrt(d.x * d.x + d.y * d.y);
        if (horizontal > 0.0)
            hi = min(hi, kReliefRepeatTravel * max(p.mapSize.x, p.mapSize.y) / horizontal);
    }
    return inside ? vec2(lo, hi) : vec2(0.0, -1.0);
}

// ---- The exact cell test and the cell cursor (cell_intersect.h, cell_cursor.h) ----

// Smallest t in [ta, tb] where the ray is on or below `plane` of the cell at (cellX, cellY),
// else kReliefInfinity (firstHitOnPlane).
float reliefFirstHitOnPlane(vec3 plane, ReliefRay ray, float cellX, float cellY, float ta,
                            float tb) {
    vec3 o = ray.origin, d = ray.direction;
    float ou = o.x - cellX, ov = o.y - cellY;
    float above0 = o.z + ta * d.z - reliefPlaneAt(plane, ou + ta * d.x, ov + ta * d.y);
    if (above0 <= 0.0) return ta;
    float above1 = o.z + tb * d.z - reliefPlaneAt(plane, ou + tb * d.x, ov + tb * d.y);
    if (above1 > 0.0) return kReliefInfinity;
    return ta + (tb - ta) * (above0 / (above0 - above1));
}

// Smallest t in [ta, tb] where the ray is on or below S in cell (ci, cj) (firstHitInCell).
float reliefFirstHitInCell(sampler2D heights, ReliefRay ray, int ci, int cj, float ta, float tb,
                           ReliefParams p) {
    vec3 first, second;
    reliefCellPlanes(reliefCellCorners(heights, ci, cj, p), first, second);
    float cellX = float(ci) + 0.5, cellY = float(cj) + 0.5;
    float t0 = reliefFirstHitOnPlane(first, ray, cellX, cellY, ta, tb);
    if (t0 == ta) return t0;
    return min(t0, reliefFirstHitOnPlane(second, ray, cellX, cellY, ta, tb));
}

float reliefExitAlong(int cell, float origin, float dir) {
    if (dir == 0.0) return kReliefInfinity;
    return (float(cell) + (dir > 0.0 ? 1.5 : 0.5) - origin) / dir;
}

// The cell the ray is in at t, moving along its direction, and where it leaves it, ≤ tEnd
// (cellAt): (ci, cj) in xy, tb in z.
struct ReliefCellSpan {
    int ci;
    int cj;
    float tb;
};

ReliefCellSpan reliefCellAt(ReliefRay ray, float t, float tEnd, ReliefParams p) {
    vec3 o = ray.origin, d = ray.direction;
    vec3 q = o + t * d;
    int ci = int(floor(q.x - 0.5)), cj = int(floor(q.y - 0.5));
    float tx = reliefExitAlong(ci, o.x, d.x), ty = reliefExitAlong(cj, o.y, d.y);
    if (tx <= t) {  // on the edge: move on
        ci += d.x > 0.0 ? 1 : -1;
        tx = reliefExitAlong(ci, o.x, d.x);
    }
    if (ty <= t) {
        cj += d.y > 0.0 ? 1 : -1;
        ty = reliefExitAlong(cj, o.y, d.y);
    }
    if (p.edge == kReliefClamp) {
        ci = clamp(ci, -1, int(p.mapSize.x) - 1);
        cj = clamp(cj, -1, int(p.mapSize.y) - 1);
    }
    return ReliefCellSpan(ci, cj, max(t, min(min(tx, ty), tEnd)));
}

// Leaving the box through its bottom face reaches z = 0 ≤ S: a hit (exitsThroughFloor).
bool reliefExitsThroughFloor(ReliefRay ray, float tExit, ReliefParams p) {
    float zExit = ray.origin.z + tExit * ray.direction.z;
    float zRounding = 4.0 * kReliefFloatEpsilon * (abs(ray.origin.z) + p.depth);
    return ray.direction.z < 0.0 && zExit <= zRounding;
}

// ---- The exact cell walk (cellsHit, surface/cell_walk.h: the safety marches, qdm paper) ----

const int kReliefCellGuard = 1048576;  // a cap valid rays never reach

// First hit on S in [ta, tb] into `t`; toExit: tb is the box exit, where leaving through the
// bottom face is a hit.
bool reliefCellsHit(sampler2D heights, ReliefRay ray, float ta, float tb, bool toExit,
                    out float tHit, inout int steps, ReliefParams p) {
    vec3 o = ray.origin, d = ray.direction;
    vec3 start = o + ta * d;
    int ci = reliefClampCellX(int(floor(start.x - 0.5)), p);
    int cj = reliefClampCellY(int(floor(start.y - 0.5)), p);
    int stepX = d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0), stepY = d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0);
    float invX = 1.0 / d.x, invY = 1.0 / d.y;
    int w = int(p.mapSize.x), h = int(p.mapSize.y);
    tHit = kReliefInfinity;
    for (int guard = 0; guard < kReliefCellGuard; ++guard) {
        float tx = stepX == 0 ? kReliefInfinity
                              : (float(ci) + (stepX > 0 ? 1.5 : 0.5) - o.x) * invX;
        float ty = stepY == 0 ? kReliefInfinity
                              : (float(cj) + (stepY > 0 ? 1.5 : 0.5) - o.y) * invY;
        float tc = max(ta, min(min(tx, ty), tb));
        ++steps;
        float t = reliefFirstHitInCell(heights, ray, ci, cj, ta, tc, p);
        if (t <= tc) {
            tHit = t;
            return true;
        }
        if (tc >= tb) {
            if (toExit && reliefExitsThroughFloor(ray, tb, p)) {
                tHit = tb;
                return true;
            }
            return false;
        }
        if (tx <= ty) ci += stepX; else cj += stepY;
        if (p.edge == kReliefClamp && (ci < -1 || ci > w - 1 || cj < -1 || cj > h - 1))
            return false;
        ta = tc;
    }
    return false;
}

// ---- Cone maps (cone, relaxed-cone: common/cone_maps.{h,glsl}) ----

const float kConeDecodeMargin = 9.5367431640625e-7;  // cone_maps.h: 2^-20

// (a, c) of the texel whose footprint holds (x, y), decoded as decodeCones decodes it.
vec2 reliefConeAt(sampler2D cones, float x, float y, ReliefParams p) {
    vec2 e = texelFetch(cones, reliefSampleIndex(int(floor(x)), int(floor(y)), p), 0).rg;
    float a = e.x, r = e.y;
    if (p.bits < 32) a = a * p.depth * (1.0 + kConeDecodeMargin);
    if (p.sqrtRatio != 0) r = r * r;
    return vec2(a, r * p.coneMax * (1.0 - kConeDecodeMargin));
}

// The largest dt that keeps the ray inside the frustum of (a, c) from height z (coneStep).
float reliefConeStep(float z, float a, float c, float horizontal, float dz) {
    float room = c * (z - a);
    float closing = horizontal - c * dz;
    if (closing <= 0.0) return room >= 0.0 ? kReliefInfinity : 0.0;
    return room / closing;
}

// ---- Shadows ----

// The linear shadow search of relief mapping (Policarpo et al. 2005 §4): `steps` bilinear
// fetches from the hit toward the light up to where the ray leaves the box (or rises above the
// relief). 1 = lit, 0 = a sample of the ray lies below the bilinear surface. The shadow query of
// the rows without a conservative map (linear, parallax, relaxed-cone).
float reliefShadowMarch(sampler2D heights, ReliefHit hit, vec3 lightDirTangent, ReliefParams p) {
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;  // the light is at or below the surface plane
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return 1.0;
    int n = max(p.maxSteps, 1);
    float dt = (span.y - span.x) / float(n);
    for (int k = 1; k <= n; ++k) {
        vec3 q = ray.origin + (span.x + float(k) * dt) * ray.direction;
        if (q.z < reliefBilinearZ(heights, q.x, q.y, p)) return 0.0;
    }
    return 1.0;
}
