// Simulated-time and real-time scheduling of the haptic loop.
#include "hapticut/haptics/loop_scheduler.h"

#include <algorithm>
#include <system_error>

#include "hapticut/common/thread_heap.h"
#include "hapticut/common/thread_priority.h"

namespace hapticut::haptics {

void runSimulated(HapticLoop& loop, long steps, const StepObserver& observer, const std::function<bool()>& keepGoing) {
    loop.setRealtime(false);
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < steps; ++i) {
        if (keepGoing && !keepGoing()) break;  // every step: one step of a large organ can take a second
        const StepOutput out = loop.step();
        if (observer) observer(out);
    }
    loop.addWallTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    loop.zeroAllForces();
}

Status RealTimeScheduler::start(long max_steps, StepObserver observer) {
    stop();
    stopRequested_ = false;
    running_ = true;
    std::vector<ServoClock*> servos = loop_.servoClocks();
    if (!servos.empty()) {
        loop_.setRealtime(true);
        return startServos(std::move(servos), max_steps, std::move(observer));
    }
    thread_ = std::thread([this, max_steps, observer = std::move(observer)] { threadMain(max_steps, observer); });
    return std::nullopt;
}

Status RealTimeScheduler::startServos(std::vector<ServoClock*> servos, long max_steps, StepObserver observer) {
    // The first device's servo thread calls the step at its own rate: no thread of ours, no sleeping.
    servoSteps_ = 0;
    servoMaxSteps_ = max_steps;
    servoObserver_ = std::move(observer);
    servoBegin_ = servoLast_ = Clock::now();
    const double period_us = 1e6 / servos.front()->servoRate_hz();
    auto drive = [this, period_us] {
        if (stopRequested_.load(std::memory_order_relaxed) || (servoMaxSteps_ >= 0 && servoSteps_ >= servoMaxSteps_)) {
            running_.store(false, std::memory_order_release);
            return false;
        }
        const auto now = Clock::now();
        if (servoSteps_ > 0)
            loop_.recordLateness(
                std::max(0.0, std::chrono::duration<double, std::micro>(now - servoLast_).count() - period_us));
        servoLast_ = now;
        const StepOutput out = loop_.step();
        if (servoObserver_) servoObserver_(out);
        ++servoSteps_;
        return true;
    };
    // The others only exchange their frames: the state the step reads, the force it wrote.
    auto follow = [this] {
        return !stopRequested_.load(std::memory_order_relaxed) && running_.load(std::memory_order_relaxed);
    };
    for (std::size_t i = 0; i < servos.size(); ++i) {
        if (Status error = i == 0 ? servos[i]->startServo(drive) : servos[i]->startServo(follow)) {
            for (std::size_t k = 0; k < i; ++k) servos[k]->stopServo();
            running_ = false;
            loop_.zeroAllForces();
            return error;
        }
    }
    servos_ = std::move(servos);
    scheduling_ = Scheduling::DeviceServo;
    return std::nullopt;
}

void RealTimeScheduler::stop() {
    stopRequested_ = true;
    if (!servos_.empty()) {
        for (ServoClock* servo : servos_) servo->stopServo();
        servos_.clear();
        loop_.addWallTime(std::chrono::duration<double>(servoLast_ - servoBegin_).count());
        loop_.zeroAllForces();
        running_.store(false, std::memory_order_release);
    }
    if (thread_.joinable()) thread_.join();
    loop_.setRealtime(false);  // a multi-rate loop's physics thread ends with it
}

std::string RealTimeScheduler::scheduling() const {
    const std::string fifo = "SCHED_FIFO " + std::to_string(loop_.hapticThreadPriority());
    switch (scheduling_.load(std::memory_order_acquire)) {
        case Scheduling::Realtime: return fifo;
        case Scheduling::Refused:
            return "normal: " + fifo + " refused (" +
                   std::error_code(schedulingError_.load(std::memory_order_relaxed), std::generic_category())
                       .message() +
                   ")";
        case Scheduling::LeftWhenBusy:
            return "normal: " + fifo + " left when more than half of " + std::to_string(kSchedulingWindowSteps) +
                   " steps had no time to sleep";
        case Scheduling::DeviceServo: return "the device's servo thread";
        case Scheduling::Normal: break;
    }
    return "normal";
}

void RealTimeScheduler::scheduleSteppingThread() {
    scheduling_ = Scheduling::Normal;
    const int priority = loop_.hapticThreadPriority();
    if (priority <= 0) return;
    const RealtimeScheduling got = scheduleRealtime(priority);
    schedulingError_.store(got.error, std::memory_order_relaxed);
    scheduling_.store(got.granted ? Scheduling::Realtime : Scheduling::Refused, std::memory_order_release);
}

void RealTimeScheduler::threadMain(long max_steps, StepObserver observer) {
    prefaultThreadHeap(kSteppingThreadHeap_bytes);
    // A multi-rate loop's physics thread starts its clock here, with the loop's, not before the heap
    // was faulted in: a sanitizer's build took tens of milliseconds over it, which the physics
    // simulated and the loop's wall time did not count (a real-time factor of 1.051). Started before
    // this thread asks for real-time scheduling, it keeps the ordinary scheduler.
    loop_.setRealtime(true);
    scheduleSteppingThread();
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1 / loop_.rate_hz()));
    // Sleep until shortly before each deadline, then spin: sleeping alone wakes up late, by more than
    // 150 us in 1% of wake-ups on a virtual machine. The spin costs CPU on the haptic thread only.
    const auto spinMargin = std::chrono::microseconds(400);
    const auto begin = Clock::now();
    auto deadline = begin;
    Clock::duration dropped{0};  // how late the next step already is when missed deadlines were dropped
    int busySteps = 0;           // in this window of kSchedulingWindowSteps: steps with no time left to sleep
    for (long i = 0; (max_steps < 0 || i < max_steps) && !stopRequested_.load(std::memory_order_relaxed); ++i) {
        const auto left = deadline - Clock::now();  // until this step's deadline
        busySteps += left <= spinMargin;
        if ((i + 1) % kSchedulingWindowSteps == 0) {
            if (2 * busySteps > kSchedulingWindowSteps &&
                scheduling_.load(std::memory_order_relaxed) == Scheduling::Realtime) {
                scheduleNormally();
                scheduling_.store(Scheduling::LeftWhenBusy, std::memory_order_release);
            }
            busySteps = 0;
        }
        if (left > spinMargin) std::this_thread::sleep_until(deadline - spinMargin);
        while (Clock::now() < deadline) {}
        loop_.recordLateness(std::chrono::duration<double, std::micro>(Clock::now() - deadline + dropped).count());
        dropped = Clock::duration{0};
        const StepOutput out = loop_.step();
        if (observer) observer(out);
        deadline += period;
        // After a long stall, drop the missed deadlines instead of racing to catch up; the next step's
        // lateness is still recorded in full, so that a run whose every step overran says so.
        if (const auto now = Clock::now(); now - deadline > 10 * period) {
            dropped = now - deadline;
            deadline = now;
        }
    }
    loop_.addWallTime(std::chrono::duration<double>(Clock::now() - begin).count());
    loop_.zeroAllForces();
    running_.store(false, std::memory_order_release);
}

}  // namespace hapticut::haptics
