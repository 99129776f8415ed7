// The machine probes: a busy loop that keeps the clock's gaps in a histogram, and timed touches of
// pages written before a sleep.
#include "bench/machine_probes.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <random>
#include <thread>
#include <vector>

#include "hapticut/common/latency_histogram.h"

namespace hapticut::bench {

using Clock = std::chrono::steady_clock;

ClockGaps measureClockGaps(double seconds) {
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

IdlePageTouches measureIdlePageTouches(double megabytes, double idle_s, int pages) {
    constexpr std::size_t kPage = 4096;
    const auto bytes = static_cast<std::size_t>(std::max(megabytes, 1.0) * (1 << 20));
    // Every byte written with different numbers, so that no page is one the kernel or a host could
    // share with another or leave unbacked.
    std::vector<std::uint64_t> memory(bytes / sizeof(std::uint64_t));
    std::mt19937_64 rng(11);
    for (std::uint64_t& word : memory) word = rng();
    std::this_thread::sleep_for(std::chrono::duration<double>(idle_s));
    const std::size_t pageCount = bytes / kPage, perPage = kPage / sizeof(std::uint64_t);
    std::vector<double> touches_us;
    touches_us.reserve(static_cast<std::size_t>(std::max(pages, 1)));
    volatile std::uint64_t sink = 0;  // so the reads are made
    for (int i = 0; i < pages; ++i) {
        const std::size_t page = rng() % pageCount;
        const auto t0 = Clock::now();
        sink = sink + *static_cast<volatile std::uint64_t*>(&memory[page * perPage]);
        touches_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    }
    IdlePageTouches result;
    result.idle_s = idle_s;
    result.pages = pages;
    if (touches_us.empty()) return result;
    std::sort(touches_us.begin(), touches_us.end());
    const auto at = [&](double q) {
        return touches_us[static_cast<std::size_t>(q * static_cast<double>(touches_us.size() - 1))];
    };
    result.p50_us = at(0.5), result.p99_us = at(0.99), result.max_us = touches_us.back();
    const auto slow =
        std::count_if(touches_us.begin(), touches_us.end(), [](double us) { return us > IdlePageTouches::kSlow_us; });
    result.slow_share = static_cast<double>(slow) / static_cast<double>(touches_us.size());
    return result;
}

}  // namespace hapticut::bench
