// Ctrl-C and SIGTERM as a request to stop: the running command lets go of its devices (zero force)
// and writes what it has, instead of dying with a motor still pushing.
#pragma once

namespace hapticut {

class StopSignal {
public:
    /// Catches SIGINT and SIGTERM until destroyed; the previous handlers come back then.
    StopSignal();
    ~StopSignal();
    StopSignal(const StopSignal&) = delete;
    StopSignal& operator=(const StopSignal&) = delete;

    /// Whether a signal asked to stop (async-signal-safe to set, lock-free to read).
    static bool requested();
    /// The signal that asked, 0 if none: the exit status is 128 + it.
    static int signalNumber();
    /// Seconds since the signal was caught on the steady clock, or a negative number if none was:
    /// how long a command took to honour it.
    static double secondsSinceRequest();
};

}  // namespace hapticut
