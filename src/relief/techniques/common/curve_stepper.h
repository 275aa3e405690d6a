#pragma once
// The stepping algorithm of Fourquet, Cowan & Mann, "Geometric Displacement on Plane and Sphere"
// (GI 2008), §4, on one visibility curve.
// Shared by the `curves` row (one ray: techniques/curves/) and the image renderer of the whole
// method (render/curves/), hence in common/.
//
// A visibility curve is parameterized by s (plane: horizontal distance from CoP_s; sphere: the
// angle θ at the centre from CoP_s). Along it the height field is height(s) and an eye ray of the
// curve's cutting plane is at height level(s) above the underlying surface. Eye rays are solved
// in order, steepest first; the state carried from one to the next is the last point reached on
// the height field. Each iteration is one "evaluation": a horizontal step to the eye ray at the
// current height (stepTo) and a vertical step to the height field (height).
//
// Conventions of this implementation where the paper is silent:
// - As in the paper's pseudo-code (§5.4, iii) the threshold is tested before the direction: a
//   horizontal step shorter than ε·Δs ends the sample whichever way it goes. A longer step from
//   a point under the ray (backwards for a descending ray) is a reverse: it bisects between the
//   last point known to lie above the height field for this ray (carried over from earlier,
//   steeper rays) and the point under it, the far end of the reverse step tightening the bracket.
//   The answer is the linear interpolation of the level difference at the bracket's ends; the
//   curve continues from the bracket's upper-side end, above the height field for later rays.
//   "Advance steps" counts every other horizontal + vertical step pair, "reverse steps" the
//   reverses that bisect, "binary cuts" the bisection evaluations.
// - A ray that does not descend has no forward horizontal step: like a step past the trailing
//   edge it ends the curve.
// - Clamp mode (DESIGN §1): a leading edge that is not CoP_s is a side wall of the solid. A ray
//   that crosses it below the height field hits the wall there; a ray that crosses it below the
//   base misses (it passes under the region). The paper leaves those rays unrendered.
#include <cmath>
#include <cstdint>
#include <limits>

namespace relief::curves {

// The paper's Table 1 quantities (plus the evaluations they add up to).
struct StepCounts {
    int64_t curves = 0;
    int64_t insideSamples = 0;
    int64_t extraSamples = 0;
    int64_t advanceSteps = 0;
    int64_t reverseSteps = 0;
    int64_t binaryCuts = 0;
    int64_t wallHits = 0;
    int64_t cappedSamples = 0;  // samples that reached the per-sample evaluation cap

    int64_t samples() const { return insideSamples + extraSamples; }
    int64_t evaluations() const { return advanceSteps + reverseSteps + binaryCuts; }
    StepCounts& operator+=(const StepCounts& o);
};

inline StepCounts& StepCounts::operator+=(const StepCounts& o) {
    curves += o.curves;
    insideSamples += o.insideSamples;
    extraSamples += o.extraSamples;
    advanceSteps += o.advanceSteps;
    reverseSteps += o.reverseSteps;
    binaryCuts += o.binaryCuts;
    wallHits += o.wallHits;
    cappedSamples += o.cappedSamples;
    return *this;
}

struct StepParams {
    double epsilon = 0.25;  // convergence threshold as a fraction of the ray spacing Δs
    int maxEvaluations = 200;  // per sample (DESIGN §3 --max-steps)
};

enum class SampleOutcome {
    Hit,       // s is the solution on the height field
    Wall,      // s is the leading edge; the ray hits the solid's side wall there
    Miss,      // this ray misses; the curve goes on
    CurveEnd,  // a horizontal step left the mapped region: this ray and every later one miss
};

struct SampleSolution {
    SampleOutcome outcome = SampleOutcome::Miss;
    double s = 0.0;
    int evaluations = 0;
};

// Where the curve stands between two eye rays.
struct CurveState {
    double s = 0.0;       // current point on the height field
    double z = 0.0;       // height(s)
    double sAbove = 0.0;  // a point above the height field for the current and all later rays
    bool aboveKnown = false;
};

// Curve: double height(double s) const; double sLead, sTrail; bool leadIsWall.
// EyeRay: double level(double s) const; double stepTo(double z) const (NaN: the ray never comes
// down to height z); double lowest() const (where the ray is lowest, NaN if it keeps descending).
template <class Curve>
CurveState startCurve(const Curve& curve) {
    CurveState state;
    state.s = curve.sLead;
    state.z = curve.height(curve.sLead);
    // At CoP_s the first ray is the one perpendicular to the surface: its solution is there and
    // that point is above the height field for every later (flatter) ray.
    state.sAbove = curve.sLead;
    state.aboveKnown = !curve.leadIsWall;
    return state;
}

namespace detail {

// `above` has the ray above the height field, `below` under it (either order); bisects down to
// tol, starting with the far end of the reverse step when it lies between them.
template <class Curve, class EyeRay>
SampleSolution bisectReverse(const Curve& curve, const EyeRay& ray, double stepEnd, double tol,
                             CurveState& st, StepCounts& counts, SampleSolution out) {
    double above = st.sAbove, below = st.s;
    double fAbove = ray.level(above) - curve.height(above), fBelow = ray.level(below) - st.z;
    if (stepEnd > std::min(above, below) && stepEnd < std::max(above, below)) {
        const double f = ray.level(stepEnd) - curve.height(stepEnd);  // the reverse's vertical step
        if (f >= 0.0) above = stepEnd, fAbove = f;
        else below = stepEnd, fBelow = f;
    }
    for (int cut = 0; cut < 64 && std::abs(below - above) > tol; ++cut) {  // 64 exhaust a double
        const double mid = 0.5 * (above + below), f = ray.level(mid) - curve.height(mid);
        ++counts.binaryCuts;
        ++out.evaluations;
        if (f >= 0.0) above = mid, fAbove = f;
        else below = mid, fBelow = f;
    }
    const double denom = fAbove - fBelow;
    out.s = denom > 0.0 ? above + (below - above) * (fAbove / denom) : below;
    out.outcome = SampleOutcome::Hit;
    st.s = above;
    st.z = curve.height(above);  // known from the cuts in a real implementation: not counted
    st.sAbove = above;
    return out;
}

}  // namespace detail

// A ray that stays above the current height everywhere (on the sphere, past the base's
// silhouette: the paper's step that "reaches outside") steps to its lowest point instead. If the
// height field is above the ray there, the next iteration is a reverse and bisects back; if not,
// the ray passes above the relief at its closest approach and the curve ends (false). On the
// plane a non-descending ray has no lowest point (NaN): the curve ends.
template <class Curve, class EyeRay>
bool stepToLowest(const Curve& curve, const EyeRay& ray, CurveState& st, StepCounts& counts,
                  SampleSolution& out) {
    const double low = ray.lowest();
    if (!(low > st.s && low <= curve.sTrail)) return false;
    ++counts.advanceSteps;
    ++out.evaluations;
    const double z = curve.height(low);
    if (ray.level(low) - z >= 0.0) return false;
    st.sAbove = st.s;
    st.s = low;
    st.z = z;
    return true;
}

// Solves one eye ray. `spacing` is Δs, the distance between this ray and the previous one on the
// underlying surface (in units of s).
template <class Curve, class EyeRay>
SampleSolution solveSample(const Curve& curve, const EyeRay& ray, double spacing,
                           const StepParams& params, CurveState& st, StepCounts& counts) {
    SampleSolution out;
    const double tol = params.epsilon * spacing;
    if (!st.aboveKnown || curve.leadIsWall) {
        const double zLead = curve.height(curve.sLead), level = ray.level(curve.sLead);
        if (level < 0.0) return out;  // passes under the region
        if (level < zLead) {
            ++counts.wallHits;
            out.outcome = SampleOutcome::Wall;
            out.s = curve.sLead;
            return out;
        }
        if (!st.aboveKnown) st.sAbove = curve.sLead, st.aboveKnown = true;
    }
    while (out.evaluations < params.maxEvaluations) {
        const bool below = ray.level(st.s) - st.z < 0.0;
        const double next = ray.stepTo(st.z);
        if (std::isnan(next) && !below) {  // the ray never comes down to st.z
            if (stepToLowest(curve, ray, st, counts, out)) continue;
            out.outcome = SampleOutcome::CurveEnd;
            return out;
        }
        if (next > curve.sTrail) {  // past the trailing edge: the paper's termination
            out.outcome = SampleOutcome::CurveEnd;
            return out;
        }
        const double step = next - st.s;
        // The paper tests the threshold before the direction: a reverse shorter than ε·Δs is a
        // converged step like any other, and only longer ones (or ones leaving the region
        // backwards) count as reverses (and bisect).
        if (below && (!(std::abs(step) < tol) || !(next >= curve.sLead))) {
            ++counts.reverseSteps;
            ++out.evaluations;
            return detail::bisectReverse(curve, ray, next, tol, st, counts, out);
        }
        ++counts.advanceSteps;
        ++out.evaluations;
        if (!below) st.sAbove = st.s;
        st.s = next;
        st.z = curve.height(next);
        if (std::abs(step) < tol) {
            out.outcome = SampleOutcome::Hit;
            out.s = next;
            return out;
        }
    }
    ++counts.cappedSamples;
    out.outcome = SampleOutcome::Hit;
    out.s = st.s;
    return out;
}

}  // namespace relief::curves
