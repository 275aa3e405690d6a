#include <relief/bench/timing.h>
#include <relief/techniques/technique.h>

#include <algorithm>
#include <ctime>
#include <fstream>

namespace relief::bench {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    const size_t middle = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + middle, values.end());
    const double upper = values[middle];
    if (values.size() % 2) return upper;
    return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + middle));
}

std::string cpuModelName() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string one, five, fifteen;
    in >> one >> five >> fifteen;
    return one.empty() ? "unknown" : one + " " + five + " " + fifteen;
}

std::string todayUtc() {
    const std::time_t now = std::time(nullptr);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    return buffer;
}

std::vector<size_t> packetOrder(int w, int h) {
    std::vector<size_t> order;
    order.reserve(size_t(w) * size_t(h));
    for (int ty = 0; ty < h; ty += 16)
        for (int tx = 0; tx < w; tx += 16)
            for (int py = ty; py < ty + 16; py += 4)
                for (int px = tx; px < tx + 16; px += 4)
                    for (int y = py; y < py + 4; ++y)
                        for (int x = px; x < px + 4; ++x) order.push_back(size_t(y) * size_t(w) + size_t(x));
    return order;
}

std::vector<Ray> inPacketOrder(const std::vector<Ray>& rays, const std::vector<size_t>& order) {
    std::vector<Ray> packed(order.size());
    for (size_t k = 0; k < order.size(); ++k) packed[k] = rays[order[k]];
    return packed;
}

vec3 towardsLight(float elevationDeg) {
    const float e = glm::radians(elevationDeg), a = glm::radians(kShadowLightAzimuth);
    return vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

std::vector<vec3> shadowPoints(const Surface& surface, std::span<const Hit> pixels, int w, int h,
                               const vec3& towardsLight) {
    std::vector<vec3> points;
    for (size_t pixel : packetOrder(w, h)) {
        const Hit& hit = pixels[pixel];
        if (hit.hit && glm::dot(surface.normalAt(hit.position), towardsLight) > 0.0f)
            points.push_back(hit.position);
    }
    return points;
}

}  // namespace relief::bench
