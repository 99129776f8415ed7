// How often this machine takes the processor away from a running thread, measured as gaps between
// consecutive clock reads of a busy loop: a virtual machine's host and the kernel's interrupts both show
// up, and they decide how far a p99 of a microsecond-long operation can fall here.
#pragma once

namespace hapticut::bench {

struct ClockGaps {
    double reads_per_s = 0;     // how fast the loop read the clock
    double gaps_per_s = 0;      // reads more than kGap_us after the one before
    double stolen_share = 0;    // the gaps' summed length over the time measured
    double median_gap_us = 0;   // the middle gap's length
    double longest_gap_us = 0;

    static constexpr double kGap_us = 1.0;
};

/// Reads the clock in a busy loop on the calling thread for `seconds`.
ClockGaps measureClockGaps(double seconds);

}  // namespace hapticut::bench
