// When the haptic loop steps: as fast as it can on simulated time, or on the wall clock in a thread of
// its own or from a device's servo loop. The loop itself (haptic_loop.h) only knows how to take a step.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/haptics/haptic_loop.h"

namespace hapticut::haptics {

using StepObserver = std::function<void(const StepOutput&)>;

/// Steps `loop` `steps` times on simulated time, as fast as it can; `observer` sees every step. A
/// `keepGoing` that returns false (asked every few steps) ends it early. The devices are left at
/// zero force afterwards.
void runSimulated(HapticLoop& loop, long steps, const StepObserver& observer = {},
                  const std::function<bool()>& keepGoing = {});

/// A stepping thread under SCHED_FIFO that, in a window of this many steps, found no time to sleep
/// before more than half of its deadlines goes back to the normal scheduler. A real-time thread that
/// never sleeps takes its core from everything else until the kernel's real-time throttling pauses it
/// (50 ms in every second by default): a stall the hand feels, and a starved physics or renderer on a
/// machine with few cores. A thread busy half the time uses at most three quarters of its core.
inline constexpr int kSchedulingWindowSteps = 100;

/// The stepping thread's malloc arena faulted in before its first step (prefaultThreadHeap): a 5 cm
/// scalpel stroke across the 1,000,000-triangle heart grew it by 0.3 MB, a page at a time.
inline constexpr std::size_t kSteppingThreadHeap_bytes = 8u << 20;

/// Steps a loop at its rate on the wall clock until stop() or a step count.
class RealTimeScheduler {
public:
    /// The loop must outlive the scheduler.
    explicit RealTimeScheduler(HapticLoop& loop) : loop_(loop) {}
    ~RealTimeScheduler() { stop(); }
    RealTimeScheduler(const RealTimeScheduler&) = delete;
    RealTimeScheduler& operator=(const RealTimeScheduler&) = delete;

    /// Starts stepping, until stop() or `max_steps` (negative: no limit). A device with its own servo
    /// loop (Device::servoClock) steps the loop from its servo thread at its own rate; otherwise a
    /// thread of ours does, at the loop's rate. With two servo devices the first one's servo steps the
    /// loop and the second's only exchanges its frame (OpenHaptics runs both in one scheduler).
    /// `observer` runs on the stepping thread: it must not block or allocate. An error when a servo
    /// cannot start.
    Status start(long max_steps = -1, StepObserver observer = {});
    /// Stops stepping and leaves the devices at zero force.
    void stop();
    bool running() const { return running_.load(std::memory_order_acquire); }
    /// How the stepping thread is scheduled, for reports and the viewer: "SCHED_FIFO 40", "normal",
    /// "normal: SCHED_FIFO 40 refused (Operation not permitted)", "normal: SCHED_FIFO 40 left when more
    /// than half of 100 steps had no time to sleep", or "the device's servo thread". Safe to call while
    /// the loop runs.
    std::string scheduling() const;

private:
    using Clock = std::chrono::steady_clock;
    Status startServos(std::vector<ServoClock*> servos, long max_steps, StepObserver observer);
    void threadMain(long max_steps, StepObserver observer);

    /// Asks for LoopConfig::hapticThreadPriority on the calling (stepping) thread and records what it got.
    void scheduleSteppingThread();

    enum class Scheduling { Normal, Realtime, Refused, LeftWhenBusy, DeviceServo };
    HapticLoop& loop_;
    std::atomic<bool> running_{false}, stopRequested_{false};
    std::atomic<Scheduling> scheduling_{Scheduling::Normal};
    std::atomic<int> schedulingError_{0};  // errno of a refusal
    std::thread thread_;
    std::vector<ServoClock*> servos_;  // set while devices' servos run: the first drives the loop
    // The servo-driven loop's own bookkeeping (what threadMain keeps on its stack).
    long servoSteps_ = 0, servoMaxSteps_ = -1;
    Clock::time_point servoBegin_{}, servoLast_{};
    StepObserver servoObserver_;
};

}  // namespace hapticut::haptics
