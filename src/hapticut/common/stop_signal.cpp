// Stop requests from signals.
#include "hapticut/common/stop_signal.h"

#include <atomic>
#include <csignal>

namespace hapticut {

namespace {
std::atomic<int> caught{0};
static_assert(std::atomic<int>::is_always_lock_free, "set from a signal handler");
using Handler = void (*)(int);
Handler previousInt = SIG_DFL, previousTerm = SIG_DFL;

extern "C" void onStopSignal(int signal) { caught.store(signal, std::memory_order_relaxed); }
}  // namespace

StopSignal::StopSignal() {
    caught = 0;
    previousInt = std::signal(SIGINT, onStopSignal);
    previousTerm = std::signal(SIGTERM, onStopSignal);
}

StopSignal::~StopSignal() {
    std::signal(SIGINT, previousInt == SIG_ERR ? SIG_DFL : previousInt);
    std::signal(SIGTERM, previousTerm == SIG_ERR ? SIG_DFL : previousTerm);
}

bool StopSignal::requested() { return caught.load(std::memory_order_relaxed) != 0; }
int StopSignal::signalNumber() { return caught.load(std::memory_order_relaxed); }

}  // namespace hapticut
