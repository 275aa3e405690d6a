#pragma once
// A paper's page (StudyKind::Paper, docs/papers/<paper>.md): its claims judged from the rows of
// the parts it ran. Each claim's value is a geometric mean of per-view ratios (numerator row over
// denominator row on the same map, view and cap) or, without a denominator, the arithmetic mean
// of the numerator's rows; the verdict is the paper variant's value against the claim's range.
#include <relief/bench/report.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace relief::bench {

struct ClaimResult {
    const ClaimSpec* spec = nullptr;
    std::optional<double> paperVariant, safeVariant;  // empty: the run lacks a side (or timings are off)
    std::string verdict;                              // "agrees", "disagrees" or "not measured"
};

// Rows per part, by the part's preset name.
using PartRows = std::map<std::string, std::vector<BenchRow>>;

std::optional<double> measureClaim(const std::vector<BenchRow>& rows, const ClaimSpec& claim,
                                   const ClaimMeasure& measure, bool timings);
std::vector<ClaimResult> judgeClaims(const BenchConfig& paper, const PartRows& parts, bool timings);

// The page: title, how it was run, the claims table, then a link and the summary per part
// (`partLinks`: part name → its report relative to the page).
std::string paperMarkdown(const BenchConfig& paper, const std::vector<ClaimResult>& claims, const BenchMeta& meta,
                          const std::map<std::string, std::string>& partLinks,
                          const std::map<std::string, std::string>& partDescriptions);
std::string claimsJson(const std::vector<ClaimResult>& claims);

}  // namespace relief::bench
