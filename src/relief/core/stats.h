#pragma once
// Summary statistics of a sample set (errors, step counts).
#include <cstddef>
#include <vector>

namespace relief {

struct Summary {
    size_t count = 0;
    double mean = 0.0;
    double p95 = 0.0;
    double p99 = 0.0;
    double max = 0.0;
};

// Sorts a copy; empty input gives all zeros.
Summary summarize(std::vector<double> values);

}  // namespace relief
