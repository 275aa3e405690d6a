#include <relief/render/curves/sampling.h>

#include <cmath>

namespace relief::curves {

double lineAngleStep(double samplesPerPixel, double farthestRadius) {
    return 1.0 / (std::sqrt(samplesPerPixel) * farthestRadius);
}

LineRadii insideRadii(double samplesPerPixel, double rTrail, double rLead) {
    LineRadii out;
    const double rootN = std::sqrt(samplesPerPixel);
    double r = rTrail;
    // Guards against a degenerate line (rTrail ≈ 0): the spacing r_0/(r√n) grows as r shrinks.
    while (r >= rLead && r > 0.0 && out.radii.size() < (1u << 22)) {
        out.radii.push_back(r);
        r -= rTrail / (r * rootN);
    }
    out.innerEnd = r;
    return out;
}

double nextOuterRadius(double samplesPerPixel, double r0, double r) {
    return 0.5 * (r + std::sqrt(r * r + 4.0 * r0 / std::sqrt(samplesPerPixel)));
}

}  // namespace relief::curves
