#include <relief/bench/paper_page.h>

#include <relief/core/check.h>

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <set>

namespace relief::bench {

namespace {

bool isTiming(ClaimMetric metric) { return metric == ClaimMetric::Speed || metric == ClaimMetric::BuildSeconds; }

// NaN where the row has no such value (a counter of the curves renderer on another row).
double metricValue(const BenchRow& r, ClaimMetric metric) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto perSample = [&](int64_t count) {
        return r.curves && r.curves->counts.samples() ? double(count) / double(r.curves->counts.samples()) : nan;
    };
    switch (metric) {
        case ClaimMetric::Speed: return r.mraysPerSecond;
        case ClaimMetric::Steps: return r.stats.steps.mean;
        case ClaimMetric::MeanError: return r.stats.error.mean;
        case ClaimMetric::WrongPercent: return 100.0 * r.stats.wrongRate();
        case ClaimMetric::PastFirstHitPercent: return 100.0 * r.stats.pastFirstHitRate();
        case ClaimMetric::BuildSeconds: return r.buildSeconds;
        case ClaimMetric::ShadowWrongPercent: return r.shadowWrongRate >= 0 ? 100.0 * r.shadowWrongRate : nan;
        case ClaimMetric::ExtraSamplesPercent:
            return r.curves && r.curves->counts.insideSamples
                       ? 100.0 * double(r.curves->counts.extraSamples) / double(r.curves->counts.insideSamples)
                       : nan;
        case ClaimMetric::AdvancePerSample: return r.curves ? perSample(r.curves->counts.advanceSteps) : nan;
        case ClaimMetric::ReversePerSample: return r.curves ? perSample(r.curves->counts.reverseSteps) : nan;
        case ClaimMetric::BinaryCutsPerReverse:
            return r.curves && r.curves->counts.reverseSteps
                       ? double(r.curves->counts.binaryCuts) / double(r.curves->counts.reverseSteps)
                       : nan;
        case ClaimMetric::EvaluationsPerSample: return r.curves ? perSample(r.curves->counts.evaluations()) : nan;
    }
    return nan;
}

// The rows of `technique` at the claim's cap: -1 its largest, else that cap; a technique without
// a cap (only cap 0 rows) matches any.
std::vector<const BenchRow*> rowsAt(const std::vector<BenchRow>& rows, const std::string& technique,
                                    const std::string& map, const ClaimSpec& claim) {
    std::set<int> caps;
    for (const BenchRow& r : rows)
        if (r.technique == technique) caps.insert(r.cap);
    if (caps.empty()) return {};
    const bool uncapped = caps.size() == 1 && *caps.begin() == 0;
    const int cap = uncapped ? 0 : claim.cap < 0 ? *caps.rbegin() : claim.cap;
    std::vector<const BenchRow*> selected;
    for (const BenchRow& r : rows)
        if (r.technique == technique && r.cap == cap && (map.empty() || r.map == map) &&
            r.elevation >= claim.minElevation && r.elevation <= claim.maxElevation)
            selected.push_back(&r);
    return selected;
}

// How each metric reads on the page: its name in the "measured" column and its value's format.
struct MetricText {
    ClaimMetric metric;
    std::string_view name, format;
};
constexpr MetricText kMetricTexts[] = {
    {ClaimMetric::Speed, "speed", "{:.3g} Mrays/s"},
    {ClaimMetric::Steps, "steps/pixel", "{:.2f} steps"},
    {ClaimMetric::MeanError, "mean |Δt|", "{:.3g} texels"},
    {ClaimMetric::WrongPercent, "wrong pixels", "{:.2f} %"},
    {ClaimMetric::PastFirstHitPercent, "pixels past the first hit", "{:.2f} %"},
    {ClaimMetric::BuildSeconds, "build s", "{:.2f} s"},
    {ClaimMetric::ShadowWrongPercent, "pixels with a wrong shadow", "{:.2f} %"},
    {ClaimMetric::ExtraSamplesPercent, "extra samples (% of inside)", "{:.1f} %"},
    {ClaimMetric::AdvancePerSample, "advance steps/sample", "{:.3g}"},
    {ClaimMetric::ReversePerSample, "reverse steps/sample", "{:.3g}"},
    {ClaimMetric::BinaryCutsPerReverse, "binary cuts/reverse", "{:.3g}"},
    {ClaimMetric::EvaluationsPerSample, "evaluations/sample", "{:.3g}"},
};

const MetricText& metricText(ClaimMetric metric) {
    for (const MetricText& t : kMetricTexts)
        if (t.metric == metric) return t;
    RELIEF_CHECK(false && "a ClaimMetric without a row in kMetricTexts");
    return kMetricTexts[0];
}

std::string formatValue(double v, ClaimMetric metric, bool ratio) {
    if (ratio) return fmt::format("{:.2f}×", v);
    return fmt::format(fmt::runtime(metricText(metric).format), v);
}

std::string_view metricName(ClaimMetric metric) { return metricText(metric).name; }

std::string rangeText(const ClaimSpec& c, bool ratio) {
    const bool hasLow = c.low > -1e299, hasHigh = c.high < 1e299;
    auto v = [&](double x) { return ratio ? fmt::format("{:g}×", x) : fmt::format("{:g}", x); };
    if (hasLow && hasHigh) return fmt::format("{} to {}", v(c.low), v(c.high));
    if (hasLow) return "≥ " + v(c.low);
    if (hasHigh) return "≤ " + v(c.high);
    return "any";
}

std::string verdictText(const ClaimResult& r, bool ratio) {
    if (r.verdict != "agrees" && r.verdict != "disagrees") return r.verdict;
    return fmt::format("{} (agrees when {})", r.verdict, rangeText(*r.spec, ratio));
}

std::string measureText(const ClaimMeasure& m) {
    auto side = [](std::string_view row, std::string_view map) {
        return map.empty() ? fmt::format("`{}`", row) : fmt::format("`{}` on {}", row, map);
    };
    if (m.denominator.empty()) return side(m.numerator, m.numeratorMap);
    return side(m.numerator, m.numeratorMap) + " / " + side(m.denominator, m.denominatorMap);
}

std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
    return out;
}

}  // namespace

std::optional<double> measureClaim(const std::vector<BenchRow>& rows, const ClaimSpec& claim,
                                   const ClaimMeasure& m, bool timings) {
    if (m.numerator.empty() || (isTiming(claim.metric) && !timings)) return std::nullopt;
    const std::vector<const BenchRow*> nums = rowsAt(rows, std::string(m.numerator), std::string(m.numeratorMap), claim);
    if (m.denominator.empty()) {
        if (nums.empty()) return std::nullopt;
        double sum = 0;
        int count = 0;
        for (const BenchRow* r : nums)
            if (const double v = metricValue(*r, claim.metric); std::isfinite(v)) {
                sum += v;
                ++count;
            }
        if (count == 0) return std::nullopt;
        return sum / count;
    }
    const std::vector<const BenchRow*> dens =
        rowsAt(rows, std::string(m.denominator), std::string(m.denominatorMap), claim);
    const bool sameMap = m.numeratorMap == m.denominatorMap;  // both empty, or the same map named twice
    double logSum = 0;
    int count = 0;
    for (const BenchRow* n : nums)
        for (const BenchRow* d : dens) {
            if (n->elevation != d->elevation || n->backend != d->backend || (sameMap && n->map != d->map)) continue;
            const double a = metricValue(*n, claim.metric), b = metricValue(*d, claim.metric);
            if (!(a > 0) || !(b > 0)) continue;  // a ratio of nothing: left out (and said on the page)
            logSum += std::log(a / b);
            ++count;
        }
    if (count == 0) return std::nullopt;
    return std::exp(logSum / count);
}

std::vector<ClaimResult> judgeClaims(const BenchConfig& paper, const PartRows& parts, bool timings) {
    std::vector<ClaimResult> results;
    static const std::vector<BenchRow> kNone;
    for (const ClaimSpec& claim : paper.claims) {
        const auto part = parts.find(std::string(claim.part));
        const std::vector<BenchRow>& rows = part == parts.end() ? kNone : part->second;
        ClaimResult r{&claim, measureClaim(rows, claim, claim.paperVariant, timings),
                      measureClaim(rows, claim, claim.safeVariant, timings), ""};
        if (!r.paperVariant)
            r.verdict = "not measured";
        else if (claim.low <= -1e299 && claim.high >= 1e299)
            r.verdict = "reported";  // a figure the paper does not give: measured, not judged
        else
            r.verdict = *r.paperVariant >= claim.low && *r.paperVariant <= claim.high ? "agrees" : "disagrees";
        results.push_back(r);
    }
    return results;
}

std::string paperMarkdown(const BenchConfig& paper, const std::vector<ClaimResult>& claims, const BenchMeta& meta,
                          const std::map<std::string, std::string>& partLinks,
                          const std::map<std::string, std::string>& partDescriptions) {
    // paperNotes: the page's title, then (after a blank line) what the run does differently from the paper.
    const size_t split = paper.paperNotes.find("\n\n");
    const std::string title = paper.paperNotes.substr(0, split);
    std::string md = fmt::format("# {}\n\n", title.empty() ? paper.name : title);
    if (split != std::string::npos) md += paper.paperNotes.substr(split + 2) + "\n\n";
    if (!paper.paperFile.empty()) md += fmt::format("Paper: `../shared/papers/{}`.\n\n", paper.paperFile);
    md += fmt::format("Generated by `{}` (every \"ours\" cell below comes from this run). Machine: {}; {} threads; "
                      "date {}.", meta.commandLine, meta.machine, meta.threads, meta.date);
    if (!meta.loadBefore.empty()) md += fmt::format(" Load average before / after: {} / {}.", meta.loadBefore, meta.loadAfter);
    md += meta.glDevice.empty() ? " GPU: not measured in this run (CPU rows only).\n\n"
                                : fmt::format(" GL device: {}.\n\n", meta.glDevice);
    md += "## Claims\n\n"
          "Each claim as the paper states it, its number, ours with the paper's own variant (the verdict is "
          "judged with it) and with our safe variant, measured as the row ratio or value named in the "
          "\"measured\" column over the views of the part that measures it. A ratio is the geometric mean of "
          "per-view ratios on the same rays; views where either side is 0 are left out of it.\n\n"
          "| claim | paper | measured | ours, paper's variant | ours, safe variant | verdict | why |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const ClaimResult& r : claims) {
        const ClaimSpec& c = *r.spec;
        const bool paperRatio = !c.paperVariant.denominator.empty(), safeRatio = !c.safeVariant.denominator.empty();
        auto value = [&](const std::optional<double>& v, bool ratio, bool present) {
            if (!present) return std::string("-");
            if (!v) return std::string(isTiming(c.metric) && !meta.timings ? "(timings off)" : "not in this run");
            return formatValue(*v, c.metric, ratio);
        };
        std::string measured = fmt::format("{} of {}", metricName(c.metric), measureText(c.paperVariant));
        if (!c.safeVariant.numerator.empty()) measured += fmt::format("; safe: {}", measureText(c.safeVariant));
        measured += fmt::format(" ({}", c.part);
        if (c.minElevation > -90 && c.maxElevation < 90)
            measured += fmt::format(", elevations {:g}°–{:g}°", c.minElevation, c.maxElevation);
        else if (c.maxElevation < 90)
            measured += fmt::format(", elevations ≤ {:g}°", c.maxElevation);
        else if (c.minElevation > -90)
            measured += fmt::format(", elevations ≥ {:g}°", c.minElevation);
        if (c.cap >= 0) measured += c.cap == 0 ? ", default cap" : fmt::format(", cap {}", c.cap);
        measured += ")";
        const std::string why(r.verdict == "agrees" ? c.whyAgrees : r.verdict == "disagrees" ? c.whyDisagrees : "");
        md += fmt::format("| {}: {} | {} | {} | {} | {} | {} | {} |\n", cell(std::string(c.source)),
                          cell(std::string(c.claim)), cell(std::string(c.paper)), cell(measured),
                          value(r.paperVariant, paperRatio, true),
                          value(r.safeVariant, safeRatio, !c.safeVariant.numerator.empty()), verdictText(r, paperRatio), cell(why));
    }
    md += "\n## Parts\n\nThe runs the claims come from, each with its full report (rows, maps, views, plots).\n\n";
    for (const std::string& part : paper.parts) {
        const auto link = partLinks.find(part);
        const auto description = partDescriptions.find(part);
        md += fmt::format("- [`{}`]({}): {}\n", part, link == partLinks.end() ? part : link->second,
                          description == partDescriptions.end() ? "" : description->second);
    }
    return md;
}

std::string claimsJson(const std::vector<ClaimResult>& claims) {
    nlohmann::json list = nlohmann::json::array();
    for (const ClaimResult& r : claims) {
        auto number = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
        list.push_back({{"source", r.spec->source}, {"claim", r.spec->claim}, {"paper", r.spec->paper},
                        {"part", r.spec->part}, {"paper_variant", number(r.paperVariant)},
                        {"safe_variant", number(r.safeVariant)}, {"verdict", r.verdict}});
    }
    return list.dump(2) + "\n";
}

}  // namespace relief::bench
