// The loop's timing histogram: percentiles within one bin of the exact ones, mean and max exact, and a
// sample past the range still counted (in the last bin) with its exact maximum.
#include <gtest/gtest.h>

#include <vector>

#include "hapticut/common/latency_histogram.h"

namespace hapticut {
namespace {

TEST(LatencyHistogram, PercentilesAreWithinOneBinOfTheExactOnes) {
    LatencyHistogram h(0.1, 20'000);
    std::vector<double> samples;
    for (int i = 1; i <= 10'000; ++i) samples.push_back(0.37 * i);  // 0.37 .. 3700 us, uniform
    for (double s : samples) h.record(s);
    const Summary exact = summarize(samples), binned = h.summary();
    EXPECT_EQ(binned.count, 10'000u);
    EXPECT_NEAR(binned.p50, exact.p50, 0.1 + 1e-9);
    EXPECT_NEAR(binned.p99, exact.p99, 0.1 + 1e-9);
    EXPECT_NEAR(binned.mean, exact.mean, 1e-9);
    EXPECT_DOUBLE_EQ(binned.max, 3700.0);
}

TEST(LatencyHistogram, ASamplePastTheRangeIsCountedWithItsExactMaximum) {
    LatencyHistogram h(1, 100);
    for (int i = 0; i < 98; ++i) h.record(10);
    h.record(250);
    h.record(5000);
    const Summary s = h.summary();
    EXPECT_EQ(s.count, 100u);
    EXPECT_DOUBLE_EQ(s.max, 5000);
    EXPECT_DOUBLE_EQ(s.mean, (98 * 10 + 250 + 5000) / 100.0);
    EXPECT_NEAR(s.p50, 11, 1e-12) << "the upper edge of the 10 us bin";
    EXPECT_GT(s.p99, 100) << "the 99th sample is past the range, and the summary says so";
}

// A run in which every step overran (a 1,000,000-triangle organ stepped explicitly): the percentiles
// are the real ones to within 1%, not the edge of the range the histogram was sized for.
TEST(LatencyHistogram, PercentilesFarPastTheRangeStayWithinOnePercent) {
    LatencyHistogram h(0.1, 20'000);
    std::vector<double> samples;
    for (int i = 1; i <= 1000; ++i) samples.push_back(30'000.0 + 97.0 * i);  // 30 ms .. 127 ms
    samples.push_back(10e6);                                                 // one 10 s step
    for (double s : samples) h.record(s);
    const Summary exact = summarize(samples), binned = h.summary();
    EXPECT_NEAR(binned.p50, exact.p50, 0.01 * exact.p50);
    EXPECT_NEAR(binned.p99, exact.p99, 0.01 * exact.p99);
    EXPECT_DOUBLE_EQ(binned.max, 10e6);
    EXPECT_GT(binned.p50, 20'000.1) << "not the range's edge";
}

TEST(LatencyHistogram, NegativeSamplesCountAsZeroAndClearStartsOver) {
    LatencyHistogram h(1, 10);
    h.record(-3);
    EXPECT_DOUBLE_EQ(h.summary().max, 0);
    h.clear();
    EXPECT_EQ(h.count(), 0u);
    EXPECT_EQ(h.summary().count, 0u);
}

}  // namespace
}  // namespace hapticut
