#include <relief/core/stats.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace relief {

Summary summarize(std::vector<double> values) {
    Summary s;
    s.count = values.size();
    if (values.empty()) return s;
    std::sort(values.begin(), values.end());
    s.mean = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
    auto quantile = [&](double q) {
        const size_t k = size_t(std::ceil(q * double(values.size()))) - 1;
        return values[std::min(k, values.size() - 1)];
    };
    s.p95 = quantile(0.95);
    s.p99 = quantile(0.99);
    s.max = values.back();
    return s;
}

}  // namespace relief
