// Rays and hits. Mirrors src/relief/core/math.h (Ray, Hit, kInfinity) and the record conversions
// of src/relief/gl/shader_interface.h (toRecord, fromRecord). C++ methods are free functions
// here with the object first: ray.at(t) is at(ray, t).

const float kInfinity = uintBitsToFloat(0x7F800000u);

// The GPU must round like the C++ (compiled without contraction, IEEE division and square root):
// rays that graze S where it lies in a face of the box (a floor of zeros) hit or miss by that
// rounding. Hence `precise` throughout the mirrored arithmetic (no fused multiply-adds, no
// reassociation), and divide() / squareRoot() for every division and root.

// a / b rounded as IEEE float division rounds it. GLSL allows 2.5 ulp (NVIDIA multiplies by an
// approximate reciprocal); a double quotient rounded to float is the correctly rounded float
// quotient (53 ≥ 2·24 + 2 bits, so the double rounding is innocuous).
float divide(float a, float b) {
    precise double q = double(a) / double(b);
    return float(q);
}

// sqrt(x) rounded as IEEE float sqrt rounds it (GLSL's sqrt is an approximation too).
float squareRoot(float x) {
    precise double r = sqrt(double(x));
    return float(r);
}

// glm::normalize: v · (1 / sqrt((x² + y²) + z²)).
vec3 normalizeLikeGlm(vec3 v) {
    precise float lengthSquared = (v.x * v.x + v.y * v.y) + v.z * v.z;
    precise vec3 unit = v * divide(1.0, squareRoot(lengthSquared));
    return unit;
}

// o + t·d, d normalized, t in [0, tMax].
struct Ray {
    vec3 origin;
    vec3 direction;
    float tMax;
};

vec3 at(Ray ray, float t) {
    precise vec3 p = ray.origin + t * ray.direction;
    return p;
}

struct Hit {
    bool hit;
    float t;
    vec3 position;
    int steps;    // iterations of the technique's main loop
    int fetches;  // map / heightfield reads
};

// `Hit hit;` in C++: a miss with no work counted.
Hit noHit() { return Hit(false, kInfinity, vec3(0.0), 0, 0); }

Ray fromRecord(RayRecord r) { return Ray(r.origin, r.direction, r.tMax); }

HitRecord toRecord(Hit hit) {
    HitRecord r;
    r.position = hit.position;
    r.t = hit.t;
    r.hit = hit.hit ? 1 : 0;
    r.steps = hit.steps;
    r.fetches = hit.fetches;
    r.pad0 = 0;
    return r;
}

// Technique parameters by index (kParam<Name>, generated from the technique's ParamSpec table).
float param(int index) { return traceUniforms.params[index / 4][index % 4]; }
int paramInt(int index) { return int(param(index)); }
