// What this machine does to a running program that the program's own figures cannot show: how often it
// takes the processor away, and how long it takes to touch memory again after the program slept. A
// virtual machine's host and the kernel both show up here, and they decide how low a p99 of a
// microsecond-long operation, or of a cut event that touches memory left alone for a while, can fall.
#pragma once

namespace hapticut::bench {

struct ClockGaps {
    double reads_per_s = 0;    // how fast the loop read the clock
    double gaps_per_s = 0;     // reads more than kGap_us after the one before
    double stolen_share = 0;   // the gaps' summed length over the time measured
    double median_gap_us = 0;  // the middle gap's length
    double longest_gap_us = 0;

    static constexpr double kGap_us = 1.0;
};

/// Reads the clock in a busy loop on the calling thread for `seconds`.
ClockGaps measureClockGaps(double seconds);

struct IdlePageTouches {
    double idle_s = 0;  // how long the thread slept before touching the pages again
    int pages = 0;      // pages touched, one byte each, in random order
    double p50_us = 0, p99_us = 0, max_us = 0;
    double slow_share = 0;  // touches over kSlow_us

    static constexpr double kSlow_us = 20.0;
};

/// Writes `megabytes` of memory, sleeps `idle_s`, then times the first read of `pages` random pages of it.
IdlePageTouches measureIdlePageTouches(double megabytes, double idle_s, int pages);

}  // namespace hapticut::bench
