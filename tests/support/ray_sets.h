#pragma once
// Random and adversarial ray sets for contract tests (fixed seeds). All rays start above S or
// outside the box, as DESIGN §3 requires.
#include <relief/core/math.h>
#include <relief/surface/surface.h>

#include <cmath>
#include <random>
#include <vector>

namespace relief::testing {

class RaySets {
public:
    RaySets(const Surface& surface, uint32_t seed) : m_s(surface), m_rng(seed) {}

    // Origins around the box (above and at the sides) aimed at random points inside it.
    std::vector<Ray> fromOutside(int count) {
        std::vector<Ray> rays;
        const vec3 size = boxSize(), centre = 0.5f * size;
        const float radius = 1.5f * glm::length(size) + 1.0f;
        for (int k = 0; k < count; ++k) {
            const float el = glm::radians(uniform(-5.0f, 89.9f)), az = uniform(0.0f, 6.2832f);
            const vec3 o = centre + radius * vec3(std::cos(el) * std::cos(az),
                                                  std::cos(el) * std::sin(az), std::sin(el));
            const vec3 target(uniform(0, size.x), uniform(0, size.y), uniform(0, size.z));
            rays.push_back(towards(o, target));
        }
        return rays;
    }

    // Origins inside the box above S, any direction (incl. upward, like shadow rays).
    std::vector<Ray> fromAboveSurface(int count) {
        std::vector<Ray> rays;
        const vec3 size = boxSize();
        for (int k = 0; k < count; ++k) {
            const float x = uniform(0, size.x), y = uniform(0, size.y);
            const float s = m_s.heightAt(x, y);
            const float z = s + 1e-3f + uniform(0.0f, std::max(1e-3f, size.z - s));
            rays.push_back(Ray{vec3(x, y, z), randomDirection(), kInfinity});
        }
        return rays;
    }

    // Grazing, axis-parallel, vertical, and origins exactly on cell edges.
    std::vector<Ray> adversarial(int count) {
        std::vector<Ray> rays;
        const vec3 size = boxSize();
        for (int k = 0; k < count; ++k) {
            const float x = uniform(0, size.x), y = uniform(0, size.y);
            const float edgeX = std::floor(x) + 0.5f, edgeY = std::floor(y) + 0.5f;
            const float top = std::max(m_s.maxZ(), 1e-3f) + 0.5f;
            switch (k % 6) {
                case 0:  // grazing from the side
                    rays.push_back(towards(vec3(-2.0f, y, uniform(0, top)),
                                           vec3(size.x, uniform(0, size.y), uniform(0, top) - 0.2f * top)));
                    break;
                case 1:  // parallel to x, slightly descending
                    rays.push_back(Ray{vec3(-1.0f, edgeY, top), glm::normalize(vec3(1, 0, -uniform(0.01f, 0.3f))), kInfinity});
                    break;
                case 2:  // parallel to y, on a cell edge in x
                    rays.push_back(Ray{vec3(edgeX, -1.0f, top), glm::normalize(vec3(0, 1, -uniform(0.01f, 0.3f))), kInfinity});
                    break;
                case 3:  // vertical, down a cell edge or a sample centre
                    rays.push_back(Ray{vec3(k % 12 == 3 ? edgeX : edgeX + 0.5f, edgeY, top), vec3(0, 0, -1), kInfinity});
                    break;
                case 4:  // diagonal through cell corners
                    rays.push_back(towards(vec3(edgeX, edgeY, top), vec3(edgeX + 3.0f, edgeY + 3.0f, 0.0f)));
                    break;
                default:  // horizontal ray just above the highest sample
                    rays.push_back(Ray{vec3(-1.0f, y, m_s.maxZ() + 1e-3f), glm::normalize(vec3(1, uniform(-0.5f, 0.5f), 0)), kInfinity});
                    break;
            }
        }
        return rays;
    }

    std::vector<Ray> all(int countPerKind) {
        std::vector<Ray> rays = fromOutside(countPerKind);
        for (auto&& set : {fromAboveSurface(countPerKind), adversarial(countPerKind)})
            rays.insert(rays.end(), set.begin(), set.end());
        return rays;
    }

private:
    vec3 boxSize() const { return vec3(float(m_s.width()), float(m_s.height()), m_s.depth()); }
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(m_rng); }
    vec3 randomDirection() {
        for (;;) {
            const vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            const float l = glm::length(v);
            if (l > 0.05f && l <= 1.0f) return v / l;
        }
    }
    static Ray towards(const vec3& from, const vec3& to) {
        return Ray{from, glm::normalize(to - from), kInfinity};
    }

    const Surface& m_s;
    std::mt19937 m_rng;
};

}  // namespace relief::testing
