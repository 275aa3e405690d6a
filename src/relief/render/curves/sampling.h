#pragma once
// Sampling along visibility lines (Fourquet et al. 2008, §5.3).
// Lines through CoP_v are spaced 1/√n pixels apart at the farthest point of the mapped region
// (angle step 1/(√n·r_max)). On a line, the first sample is at the trailing edge, r_0, and
// r_j = r_{j−1} − r_0/(r_{j−1}√n) until a sample passes the leading edge or zero: the spacing
// along the line, r_0/(r√n), times the spacing between lines, r/(r_max√n), is 1/n pixel² when
// r_0 = r_max, so the density is about n samples per pixel. Extra samples past the trailing edge
// invert the recurrence: r_{j−1} = (r_j + √(r_j² + 4r_0/√n))/2.
// Jitter: sample j lies uniformly in its own interval [r_{j+1}, r_j] along the line (never off
// it), so jittered samples keep their order.
#include <cstdint>
#include <random>
#include <vector>

namespace relief::curves {

// Angle step between visibility lines for n samples per pixel.
double lineAngleStep(double samplesPerPixel, double farthestRadius);

// Unjittered radii r_0 > r_1 > … from the trailing edge inwards, stopping before the first one
// below rLead or ≤ 0. Also returns r_last: the radius after the final one (the inner end of the
// final interval).
struct LineRadii {
    std::vector<double> radii;
    double innerEnd = 0.0;
};
LineRadii insideRadii(double samplesPerPixel, double rTrail, double rLead);

// The radius beyond r on the same line (inverse recurrence with the line's r_0).
double nextOuterRadius(double samplesPerPixel, double r0, double r);

// Jittered position in the interval [inner, outer].
class LineJitter {
public:
    explicit LineJitter(uint64_t seed) : m_rng(seed) {}
    double place(double inner, double outer) {
        return inner + (outer - inner) * m_uniform(m_rng);
    }

private:
    std::mt19937_64 m_rng;
    std::uniform_real_distribution<double> m_uniform{0.0, 1.0};
};

}  // namespace relief::curves
