// Rays and hits. Mirrors src/relief/core/math.h (Ray, Hit, kInfinity) and the record conversions
// of src/relief/gl/shader_interface.h (toRecord, fromRecord). C++ methods are free functions
// here with the object first: ray.at(t) is at(ray, t).

const float kInfinity = uintBitsToFloat(0x7F800000u);

// o + t·d, d normalized, t in [0, tMax].
struct Ray {
    vec3 origin;
    vec3 direction;
    float tMax;
};

vec3 at(Ray ray, float t) { return ray.origin + t * ray.direction; }

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
