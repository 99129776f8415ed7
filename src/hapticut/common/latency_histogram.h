// Fixed-size histogram of durations in microseconds: record without allocating, read percentiles later.
// Fine linear bins up to a range, then bins 1% wide up to 1000 s, so that a run whose steps all take
// far longer than expected still reports their percentiles truthfully instead of the range's edge.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hapticut/common/stats.h"

namespace hapticut {

class LatencyHistogram {
public:
    /// Bins of `resolution_us` up to `range_us`, then 1% wide up to kLongest_us; longer samples land in
    /// the last bin (max stays exact).
    explicit LatencyHistogram(double resolution_us = 0.1, double range_us = 20'000)
        : resolution_(resolution_us),
          linearBins_(static_cast<std::size_t>(range_us / resolution_us) + 1),
          range_(static_cast<double>(linearBins_) * resolution_us),
          bins_(linearBins_ + wideBins(range_), 0) {}

    static constexpr double kLongest_us = 1e9;  // 1000 s
    static constexpr double kWideRatio = 1.01;

    void record(double us) noexcept {
        const double clamped = std::max(us, 0.0);
        const std::size_t bin =
            clamped < range_
                ? static_cast<std::size_t>(clamped / resolution_)
                : std::min(linearBins_ + static_cast<std::size_t>(std::log(clamped / range_) / std::log(kWideRatio)),
                           bins_.size() - 1);
        ++bins_[bin];
        ++count_;
        sum_ += clamped;
        max_ = std::max(max_, clamped);
    }
    void clear() noexcept {
        std::fill(bins_.begin(), bins_.end(), 0);
        count_ = 0;
        sum_ = max_ = 0;
    }
    std::uint64_t count() const { return count_; }

    /// Mean and max are exact; p50 and p99 are the upper edges of their bins (nearest rank).
    Summary summary() const {
        Summary s;
        s.count = count_;
        if (count_ == 0) return s;
        s.mean = sum_ / static_cast<double>(count_);
        s.max = max_;
        s.p50 = std::min(percentile(0.50), max_);
        s.p99 = std::min(percentile(0.99), max_);
        return s;
    }

private:
    static std::size_t wideBins(double from_us) {
        return static_cast<std::size_t>(std::ceil(std::log(kLongest_us / from_us) / std::log(kWideRatio))) + 1;
    }
    /// The upper edge of bin i.
    double upperEdge(std::size_t i) const {
        if (i < linearBins_) return static_cast<double>(i + 1) * resolution_;
        return range_ * std::pow(kWideRatio, static_cast<double>(i - linearBins_ + 1));
    }
    double percentile(double p) const {
        const auto rank = static_cast<std::uint64_t>(p * static_cast<double>(count_) + 0.999999);
        std::uint64_t seen = 0;
        for (std::size_t i = 0; i < bins_.size(); ++i)
            if ((seen += bins_[i]) >= rank) return upperEdge(i);
        return max_;
    }

    double resolution_;
    std::size_t linearBins_;
    double range_;  // where the linear bins end
    std::vector<std::uint32_t> bins_;
    std::uint64_t count_ = 0;
    double sum_ = 0, max_ = 0;
};

}  // namespace hapticut
