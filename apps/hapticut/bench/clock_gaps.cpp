// The clock-gap probe: a busy loop that keeps the gaps' lengths in a histogram.
#include "bench/clock_gaps.h"

#include <chrono>

#include "hapticut/common/latency_histogram.h"

namespace hapticut::bench {

ClockGaps measureClockGaps(double seconds) {
    using Clock = std::chrono::steady_clock;
    LatencyHistogram gaps(0.05, 1'000);
    double stolen_us = 0;
    long reads = 0;
    const auto start = Clock::now();
    const auto end = start + std::chrono::duration<double>(seconds);
    auto last = start;
    for (auto now = last; now < end; last = now) {
        now = Clock::now();
        ++reads;
        const double gap_us = std::chrono::duration<double, std::micro>(now - last).count();
        if (gap_us > ClockGaps::kGap_us) gaps.record(gap_us), stolen_us += gap_us;
    }
    const double measured_s = std::chrono::duration<double>(last - start).count();
    const Summary s = gaps.summary();
    ClockGaps result;
    if (measured_s <= 0) return result;
    result.reads_per_s = static_cast<double>(reads) / measured_s;
    result.gaps_per_s = static_cast<double>(s.count) / measured_s;
    result.stolen_share = stolen_us * 1e-6 / measured_s;
    result.median_gap_us = s.p50;
    result.longest_gap_us = s.max;
    return result;
}

}  // namespace hapticut::bench
