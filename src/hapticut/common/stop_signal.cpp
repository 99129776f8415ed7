// Stop requests from signals.
#include "hapticut/common/stop_signal.h"

#include <atomic>
#include <csignal>
#include <cstdint>
#include <ctime>

namespace hapticut {

namespace {
std::atomic<int> caught{0};
std::atomic<std::int64_t> caughtAt_ns{0};  // CLOCK_MONOTONIC, which std::chrono::steady_clock reads on Linux
static_assert(std::atomic<int>::is_always_lock_free, "set from a signal handler");
static_assert(std::atomic<std::int64_t>::is_always_lock_free, "set from a signal handler");

std::int64_t monotonicNow_ns() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe, unlike the C++ clocks by the letter of the standard
    return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}
using Handler = void (*)(int);
Handler previousInt = SIG_DFL, previousTerm = SIG_DFL;

extern "C" void onStopSignal(int signal) {
    if (caught.load(std::memory_order_relaxed) == 0) caughtAt_ns.store(monotonicNow_ns(), std::memory_order_relaxed);
    caught.store(signal, std::memory_order_release);
}
}  // namespace

StopSignal::StopSignal() {
    caught = 0;
    caughtAt_ns = 0;
    previousInt = std::signal(SIGINT, onStopSignal);
    previousTerm = std::signal(SIGTERM, onStopSignal);
}

StopSignal::~StopSignal() {
    std::signal(SIGINT, previousInt == SIG_ERR ? SIG_DFL : previousInt);
    std::signal(SIGTERM, previousTerm == SIG_ERR ? SIG_DFL : previousTerm);
}

bool StopSignal::requested() { return caught.load(std::memory_order_relaxed) != 0; }
int StopSignal::signalNumber() { return caught.load(std::memory_order_relaxed); }
double StopSignal::secondsSinceRequest() {
    if (caught.load(std::memory_order_acquire) == 0) return -1;
    return 1e-9 * static_cast<double>(monotonicNow_ns() - caughtAt_ns.load(std::memory_order_relaxed));
}

}  // namespace hapticut
