// Summary statistics (mean and percentiles) of timing samples.
#include "hapticut/common/stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hapticut {

namespace {
// Nearest-rank percentile: the smallest sample with at least p of the samples at or below it.
double percentile(const std::vector<double>& sorted, double p) {
    const auto n = sorted.size();
    auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(n)));
    rank = std::clamp<std::size_t>(rank, 1, n);
    return sorted[rank - 1];
}
}  // namespace

Summary summarize(std::span<const double> samples) {
    Summary s;
    s.count = samples.size();
    if (samples.empty()) return s;
    std::vector<double> sorted(samples.begin(), samples.end());
    std::sort(sorted.begin(), sorted.end());
    s.mean = std::accumulate(sorted.begin(), sorted.end(), 0.0) / static_cast<double>(sorted.size());
    s.p50 = percentile(sorted, 0.50);
    s.p99 = percentile(sorted, 0.99);
    s.min = sorted.front();
    s.max = sorted.back();
    return s;
}

}  // namespace hapticut
