// TEST DOUBLE: an emulation of the subset of OpenHaptics' HD API that Hapticut uses, built as a shared
// library and loaded through the very same dlopen path as the vendor's libHD.so. A scheduler thread
// calls the scheduled callbacks at 1 kHz; a simulated stylus sits where the test puts it; hdEmu_*
// functions let tests inject faults and read back what the device was told.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "hapticut/haptics/hd_api.h"

using namespace hapticut::haptics::hd;

namespace {

struct Scheduled {
    HDSchedulerHandle handle;
    HDSchedulerCallback callback;
    void* data;
};

struct Emulation {
    std::recursive_mutex mutex;  // held while callbacks run, so unscheduling waits for a running one
    std::vector<HDErrorInfo> errors;
    std::vector<Scheduled> scheduled;
    HDSchedulerHandle nextHandle = 1;
    std::thread scheduler;
    std::atomic<bool> schedulerRunning{false};
    bool deviceOpen = false, inFrame = false, forceOutput = false;
    HDerror failInitWith = kSuccess;
    HDenum calibration = kCalibrationOk;
    long calibrationUpdates = 0;
    long failAfterTicks = -1;
    HDerror failWith = kSuccess;
    std::atomic<long> ticks{0};
    std::atomic<long> ticksWithCallbacks{0};  // the ticks that ran at least one scheduled callback
    std::atomic<long> stallMs{0};             // the scheduler's next tick is held back this long (a stalled servo)
    long frameErrors = 0, forcesOutsideFrame = 0;
    double position[3] = {0, 0, 0}, velocity[3] = {0, 0, 0};
    int buttons = 0;
    double force[3] = {0, 0, 0}, maxForceSent = 0;
    double nominalMaxForce = 3.3, nominalMaxContinuousForce = 0.9, nominalMaxStiffness = 0.8;  // N, N, N/mm
};

Emulation& emu() {
    static Emulation e;
    return e;
}

void pushError(HDerror code, int internal = 0) { emu().errors.push_back({code, internal, 0}); }

void schedulerMain() {
    Emulation& e = emu();
    auto next = std::chrono::steady_clock::now();
    while (e.schedulerRunning.load()) {
        next += std::chrono::microseconds(1000);
        std::this_thread::sleep_until(next);
        if (const long ms = e.stallMs.exchange(0); ms > 0) {
            std::this_thread::sleep_for(std::chrono::milliseconds(ms));
            next = std::chrono::steady_clock::now();  // a stalled scheduler resumes; it does not replay missed ticks
        }
        std::lock_guard lock(e.mutex);
        ++e.ticks;
        if (e.failAfterTicks >= 0 && e.ticks > e.failAfterTicks) pushError(e.failWith, 5);
        if (!e.scheduled.empty()) ++e.ticksWithCallbacks;
        for (std::size_t i = 0; i < e.scheduled.size();) {
            if (e.scheduled[i].callback(e.scheduled[i].data) == kCallbackDone)
                e.scheduled.erase(e.scheduled.begin() + static_cast<std::ptrdiff_t>(i));
            else
                ++i;
        }
    }
}

}  // namespace

extern "C" {

HHD hdInitDevice(HDstring) {
    Emulation& e = emu();
    std::lock_guard lock(e.mutex);
    if (e.failInitWith != kSuccess) {
        pushError(e.failInitWith);
        return kInvalidHandle;
    }
    if (e.deviceOpen) {
        pushError(kDeviceAlreadyInitiated);
        return kInvalidHandle;
    }
    e.deviceOpen = true;
    return 1;
}

void hdDisableDevice(HHD) {
    std::lock_guard lock(emu().mutex);
    emu().deviceOpen = false;
    emu().forceOutput = false;
}

void hdEnable(HDenum cap) {
    std::lock_guard lock(emu().mutex);
    if (cap == kForceOutput) emu().forceOutput = true;
}

void hdStartScheduler() {
    Emulation& e = emu();
    if (e.schedulerRunning.exchange(true)) return;
    e.scheduler = std::thread(schedulerMain);
}

void hdStopScheduler() {
    Emulation& e = emu();
    if (!e.schedulerRunning.exchange(false)) return;
    if (e.scheduler.joinable()) e.scheduler.join();
}

HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback callback, void* data, HDushort) {
    std::lock_guard lock(emu().mutex);
    const HDSchedulerHandle h = emu().nextHandle++;
    emu().scheduled.push_back({h, callback, data});
    return h;
}

void hdScheduleSynchronous(HDSchedulerCallback callback, void* data, HDushort) {
    // Runs once in a servo tick's place; the emulation runs it here, under the scheduler's lock.
    std::lock_guard lock(emu().mutex);
    while (callback(data) != kCallbackDone) {}
}

void hdUnschedule(HDSchedulerHandle handle) {
    std::lock_guard lock(emu().mutex);
    auto& s = emu().scheduled;
    s.erase(std::remove_if(s.begin(), s.end(), [&](const Scheduled& x) { return x.handle == handle; }), s.end());
}

void hdBeginFrame(HHD) {
    Emulation& e = emu();
    if (e.inFrame) ++e.frameErrors;
    e.inFrame = true;
}

void hdEndFrame(HHD) {
    Emulation& e = emu();
    if (!e.inFrame) ++e.frameErrors;
    e.inFrame = false;
}

void hdGetDoublev(HDenum what, HDdouble* out) {
    Emulation& e = emu();
    switch (what) {
        case kCurrentPosition: std::memcpy(out, e.position, sizeof e.position); break;
        case kCurrentVelocity: std::memcpy(out, e.velocity, sizeof e.velocity); break;
        case kCurrentTransform: {
            const double identity[16] = {
                1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, e.position[0], e.position[1], e.position[2], 1};
            std::memcpy(out, identity, sizeof identity);
            break;
        }
        case kNominalMaxForce: *out = e.nominalMaxForce; break;
        case kNominalMaxContinuousForce: *out = e.nominalMaxContinuousForce; break;
        case kNominalMaxStiffness: *out = e.nominalMaxStiffness; break;
        case kUsableWorkspaceDimensions: {
            // A Touch's: 160 x 120 x 70 mm round the inkwell-calibrated origin.
            const double box[6] = {-80, -60, -35, 80, 60, 35};
            std::memcpy(out, box, sizeof box);
            break;
        }
        default: pushError(0x0100);  // HD_INVALID_ENUM
    }
}

void hdGetIntegerv(HDenum what, HDint* out) {
    Emulation& e = emu();
    switch (what) {
        case kCurrentButtons: *out = e.buttons; break;
        case kUpdateRate: *out = 1000; break;
        case static_cast<HDenum>(kCalibrationStyle): *out = kCalibrationAuto | kCalibrationInkwell; break;
        default: pushError(0x0100);
    }
}

void hdSetDoublev(HDenum what, const HDdouble* in) {
    Emulation& e = emu();
    if (what != kCurrentForce) {
        pushError(0x0100);
        return;
    }
    if (!e.inFrame) ++e.forcesOutsideFrame;
    std::memcpy(e.force, in, sizeof e.force);
    e.maxForceSent = std::max(e.maxForceSent, std::sqrt(in[0] * in[0] + in[1] * in[1] + in[2] * in[2]));
}

HDstring hdGetString(HDenum what) {
    if (what == kDeviceModelType) return "Emulated Touch";
    if (what == kDeviceSerialNumber) return "EMU-0001";
    return "";
}

HDErrorInfo hdGetError() {
    Emulation& e = emu();
    std::lock_guard lock(e.mutex);
    if (e.errors.empty()) return {kSuccess, 0, 0};
    const HDErrorInfo top = e.errors.back();
    e.errors.pop_back();
    return top;
}

HDstring hdGetErrorString(HDerror code) {
    return code == kCommError ? "emulated communication error" : "emulated error";
}

HDenum hdCheckCalibration() { return emu().calibration; }

#ifndef HD_EMULATION_WITHOUT_UPDATE_CALIBRATION
void hdUpdateCalibration(HDenum) {
    ++emu().calibrationUpdates;
    emu().calibration = kCalibrationOk;
}
#endif

// ---- Test controls ----

void hdEmu_reset() {
    hdStopScheduler();
    Emulation& e = emu();
    std::lock_guard lock(e.mutex);
    e.errors.clear();
    e.scheduled.clear();
    e.deviceOpen = e.inFrame = e.forceOutput = false;
    e.failInitWith = kSuccess;
    e.calibration = kCalibrationOk;
    e.calibrationUpdates = 0;
    e.failAfterTicks = -1;
    e.ticks = 0;
    e.ticksWithCallbacks = 0;
    e.frameErrors = e.forcesOutsideFrame = 0;
    std::fill(std::begin(e.position), std::end(e.position), 0.0);
    std::fill(std::begin(e.force), std::end(e.force), 0.0);
    e.buttons = 0;
    e.maxForceSent = 0;
}
void hdEmu_setPosition(double x_mm, double y_mm, double z_mm) {
    std::lock_guard lock(emu().mutex);
    emu().position[0] = x_mm, emu().position[1] = y_mm, emu().position[2] = z_mm;
}
void hdEmu_setButtons(int buttons) { emu().buttons = buttons; }
void hdEmu_setCalibration(HDenum status) { emu().calibration = status; }
void hdEmu_failInit(HDerror code) { emu().failInitWith = code; }
void hdEmu_failAfterTicks(long ticks, HDerror code) {
    std::lock_guard lock(emu().mutex);
    emu().failAfterTicks = emu().ticks + ticks;
    emu().failWith = code;
}
void hdEmu_lastForce(double out[3]) {
    std::lock_guard lock(emu().mutex);
    std::memcpy(out, emu().force, sizeof emu().force);
}
double hdEmu_maxForceSent() {  // read while the servo thread runs, as lastForce is
    std::lock_guard lock(emu().mutex);
    return emu().maxForceSent;
}
long hdEmu_ticks() { return emu().ticks; }
long hdEmu_ticksWithCallbacks() { return emu().ticksWithCallbacks; }
void hdEmu_stallScheduler(long ms) { emu().stallMs = ms; }
long hdEmu_calibrationUpdates() { return emu().calibrationUpdates; }
long hdEmu_frameErrors() { return emu().frameErrors + emu().forcesOutsideFrame; }
int hdEmu_deviceOpen() { return emu().deviceOpen; }
int hdEmu_forceOutput() { return emu().forceOutput; }
int hdEmu_schedulerRunning() { return emu().schedulerRunning; }
long hdEmu_scheduledCallbacks() {
    std::lock_guard lock(emu().mutex);
    return static_cast<long>(emu().scheduled.size());
}

}  // extern "C"
