// Summary statistics (mean and percentiles) of timing samples, for reports and benchmarks.
#pragma once

#include <span>
#include <vector>

namespace hapticut {

struct Summary {
    double mean = 0, p50 = 0, p99 = 0, max = 0, min = 0;
    std::size_t count = 0;
};

/// Summarises samples; sorts a copy, so call it after a run, never inside the loop.
Summary summarize(std::span<const double> samples);

}  // namespace hapticut
