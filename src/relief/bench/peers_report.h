#pragma once
// The cpu-peers page (issue 21): every CPU row against Embree on the same rays of each view,
// primary rays against rtcIntersect1/16 and shadow rays against rtcOccluded1/16, geometric means,
// the bakes, and the targets (BenchConfig::targets) judged met or not from the rows.
#include <relief/bench/report.h>

#include <string_view>
#include <vector>

namespace relief::bench {

// The instruction set the CPU tracers run with, for the page's ISA line.
std::string_view benchIsa();

// Empty without timings (--deterministic): every number on the page is a speed.
std::vector<ReportTable> cpuPeersTables(const std::vector<BenchRow>& rows,
                                        const BenchConfig& config, const BenchMeta& meta);

}  // namespace relief::bench
