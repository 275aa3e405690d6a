#pragma once
// Vector math for relief: GLM types under short names, rays and hits in texel space (DESIGN §1, §3).
#include <glm/glm.hpp>

#include <cstdint>
#include <limits>

namespace relief {

using glm::dvec3;
using glm::ivec2;
using glm::vec2;
using glm::vec3;
using glm::vec4;

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// o + t·d, d normalized, t in [0, tMax].
struct Ray {
    vec3 origin{0.0f};
    vec3 direction{0.0f, 0.0f, -1.0f};
    float tMax = kInfinity;

    vec3 at(float t) const { return origin + t * direction; }
};

// What a tracer reports for one ray. `position` is always origin + t·direction.
struct Hit {
    bool hit = false;
    float t = kInfinity;
    vec3 position{0.0f};
    int32_t steps = 0;    // iterations of the technique's main loop
    int32_t fetches = 0;  // map / heightfield reads
};

}  // namespace relief
