#pragma once
// How the bench times and describes a run: best-of-N wall time, process CPU time, the load
// average, the CPU model and the date, the 4×4 packet order of Embree's rtcIntersect16, and the
// shadow rays' points.
#include <relief/core/math.h>
#include <relief/surface/surface.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace relief::bench {

double secondsSince(std::chrono::steady_clock::time_point start);
// CPU seconds used by this process so far (all threads).
double processCpuSeconds();

// Best wall time of `repeats` (at least one) runs of fn: the machine is shared and noisy, the
// best run is the one least disturbed.
template <class Fn>
double bestOf(int repeats, Fn&& fn) {
    double best = 1e300;
    for (int r = 0; r < (repeats < 1 ? 1 : repeats); ++r) {
        const auto start = std::chrono::steady_clock::now();
        fn();
        best = std::min(best, secondsSince(start));
    }
    return best;
}

// The middle value (the mean of the two middle ones for an even count); 0 for none.
double median(std::vector<double> values);

// Wall and process CPU seconds of one run of fn.
struct Elapsed {
    double wall = 0, cpu = 0;
};
template <class Fn>
Elapsed timeOnce(Fn&& fn) {
    const double cpu = processCpuSeconds();
    const auto start = std::chrono::steady_clock::now();
    fn();
    return {secondsSince(start), processCpuSeconds() - cpu};
}

std::string cpuModelName();   // "model name" from /proc/cpuinfo
std::string loadAverage();    // the 1, 5 and 15 minute load averages
std::string todayUtc();       // "YYYY-MM-DD HH:MM UTC"

// Pixel indices in 4×4 packets inside 16×16 tiles (w and h multiples of 16): 16 consecutive rays
// are one rtcIntersect16 packet, 256 one parallel work item.
std::vector<size_t> packetOrder(int w, int h);
// The rays in that order: inPacketOrder(rays, order)[k] = rays[order[k]].
std::vector<Ray> inPacketOrder(const std::vector<Ray>& rays, const std::vector<size_t>& order);

// The unit vector toward StudySpec::shadowElevation's light (azimuth kShadowLightAzimuth).
vec3 towardsLight(float elevationDeg);
// The shadow rays' points: the primary hits (one per pixel, w×h by rows) whose normals face the
// light, in packetOrder (coherent shadow rays for every row and peer).
std::vector<vec3> shadowPoints(const Surface& surface, std::span<const Hit> pixels, int w, int h,
                               const vec3& towardsLight);

}  // namespace relief::bench
