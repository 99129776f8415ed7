// OpenHaptics through dlopen: resolve, initialise, calibrate, and step the loop in the HD servo loop.
#include "hapticut/haptics/openhaptics_device.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <thread>

namespace hapticut::haptics {

const char* hd::describeError(HDerror code) {
    switch (code) {
        case kSuccess: return "no error";
        case kWarmMotors: return "the motors are too warm: the device limits its force until they cool down";
        case kExceededMaxForce: return "the force exceeded the device's maximum";
        case kExceededMaxForceImpulse: return "the force changed faster than the device allows (a kick)";
        case kExceededMaxVelocity: return "the stylus moved faster than the device allows";
        case kForceError: return "the device could not render the force";
        case kDeviceFault: return "the device reported a fault";
        case kDeviceAlreadyInitiated: return "the device is already in use (another program, or opened twice)";
        case kCommError:
            return "communication with the device failed: is it plugged in and powered, and its driver running?";
        case kCommConfigError: return "the device's communication is misconfigured: run the vendor's setup tool";
        case kTimerError: return "the servo timer failed";
        case kInvalidLicense: return "the OpenHaptics licence is invalid";
        default: return "an HD API error";
    }
}

// Exactly the functions Hapticut calls; each is resolved by name from the HD library.
struct OpenHapticsDevice::Api {
    hd::HHD (*initDevice)(hd::HDstring) = nullptr;
    void (*disableDevice)(hd::HHD) = nullptr;
    void (*enable)(hd::HDenum) = nullptr;
    void (*startScheduler)() = nullptr;
    void (*stopScheduler)() = nullptr;
    hd::HDSchedulerHandle (*scheduleAsynchronous)(hd::HDSchedulerCallback, void*, hd::HDushort) = nullptr;
    void (*scheduleSynchronous)(hd::HDSchedulerCallback, void*, hd::HDushort) = nullptr;
    void (*unschedule)(hd::HDSchedulerHandle) = nullptr;
    void (*beginFrame)(hd::HHD) = nullptr;
    void (*endFrame)(hd::HHD) = nullptr;
    void (*getDoublev)(hd::HDenum, hd::HDdouble*) = nullptr;
    void (*getIntegerv)(hd::HDenum, hd::HDint*) = nullptr;
    void (*setDoublev)(hd::HDenum, const hd::HDdouble*) = nullptr;
    hd::HDstring (*getString)(hd::HDenum) = nullptr;
    hd::HDErrorInfo (*getError)() = nullptr;
    hd::HDstring (*getErrorString)(hd::HDerror) = nullptr;
    hd::HDenum (*checkCalibration)() = nullptr;
    void (*updateCalibration)(hd::HDenum) = nullptr;
};

std::vector<std::string> defaultHdLibraryNames() {
    if (const char* chosen = std::getenv("HAPTICUT_HD_LIBRARY"); chosen && *chosen) return {chosen};
#ifdef _WIN32
    return {"HD.dll", "hd.dll"};
#else
    return {"libHD.so", "libHD.so.3.4", "libHD.so.3.0", "libHD.so.3"};
#endif
}

std::vector<std::string> defaultHdSearchFolders() {
    return {"",
            "/usr/lib",
            "/usr/lib64",
            "/usr/local/lib",
            "/usr/lib/x86_64-linux-gnu",
            "/opt/OpenHaptics/Developer/3.4-0/lib",
            "/opt/OpenHaptics/Developer/3.5.0/lib",
            "/opt/OpenHaptics/lib"};
}

std::string OpenHapticsDevice::takeError() {
    const hd::HDErrorInfo e = api_->getError();
    if (e.errorCode == hd::kSuccess) return {};
    char code[64];
    std::snprintf(code, sizeof code, " (HD error 0x%04x, internal %d)", e.errorCode, e.internalErrorCode);
    std::string text = hd::describeError(e.errorCode);
    if (const char* own = api_->getErrorString ? api_->getErrorString(e.errorCode) : nullptr; own && *own)
        text += "; the library says: " + std::string(own);
    return text + code;
}

bool OpenHapticsDevice::load(std::string& error) {
    const std::vector<std::string> names =
        options_.libraryNames.empty() ? defaultHdLibraryNames() : options_.libraryNames;
    const std::vector<std::string> folders =
        options_.searchFolders.empty() ? defaultHdSearchFolders() : options_.searchFolders;
    std::string why;
    library_ = SharedLibrary::open(names, folders, why);
    if (!library_) {
        error = "OpenHaptics: the HD runtime library is not installed here, " + why +
                "\nInstall the OpenHaptics runtime (and the Touch/Phantom device driver) from the vendor, or point "
                "HAPTICUT_HD_LIBRARY at libHD.so.";
        return false;
    }
    api_ = std::make_unique<Api>();
    Api& a = *api_;
    const SharedLibrary& lib = *library_;
    std::vector<std::string> missing;
    const auto need = [&](const char* symbol, auto& function) {
        if (!lib.resolve(symbol, function)) missing.push_back(symbol);
    };
    need("hdInitDevice", a.initDevice);
    need("hdDisableDevice", a.disableDevice);
    need("hdEnable", a.enable);
    need("hdStartScheduler", a.startScheduler);
    need("hdStopScheduler", a.stopScheduler);
    need("hdScheduleAsynchronous", a.scheduleAsynchronous);
    need("hdScheduleSynchronous", a.scheduleSynchronous);
    need("hdUnschedule", a.unschedule);
    need("hdBeginFrame", a.beginFrame);
    need("hdEndFrame", a.endFrame);
    need("hdGetDoublev", a.getDoublev);
    need("hdGetIntegerv", a.getIntegerv);
    need("hdSetDoublev", a.setDoublev);
    need("hdGetString", a.getString);
    need("hdGetError", a.getError);
    need("hdCheckCalibration", a.checkCalibration);
    need("hdUpdateCalibration", a.updateCalibration);
    lib.resolve("hdGetErrorString", a.getErrorString);  // optional: only improves messages
    if (!missing.empty()) {
        error = "OpenHaptics: " + lib.path() + " lacks";
        for (const std::string& m : missing) error += " " + m;
        error +=
            ": it is not the HD API library, or a version Hapticut does not support (install OpenHaptics 3.4 or later)";
        return false;
    }
    return true;
}

Result<std::string, Error> OpenHapticsDevice::probeLibrary(const OpenHapticsOptions& options) {
    OpenHapticsDevice d;
    d.options_ = options;
    std::string error;
    if (!d.load(error)) return unexpected(Error{{}, 0, error});
    return d.library_->path();
}

Result<std::unique_ptr<OpenHapticsDevice>, Error> OpenHapticsDevice::open(const OpenHapticsOptions& options) {
    std::string error;
    auto device = openOrExplain(options, error);
    if (!device) return unexpected(Error{{}, 0, error});
    return device;
}

std::unique_ptr<OpenHapticsDevice> OpenHapticsDevice::openOrExplain(const OpenHapticsOptions& options,
                                                                    std::string& error) {
    auto d = std::unique_ptr<OpenHapticsDevice>(new OpenHapticsDevice);
    d->options_ = options;
    if (!d->load(error)) return nullptr;
    Api& a = *d->api_;
    d->device_ = a.initDevice(options.deviceName.empty() ? nullptr : options.deviceName.c_str());
    if (const std::string e = d->takeError(); !e.empty() || d->device_ == hd::kInvalidHandle) {
        error = "OpenHaptics: cannot open the device " +
                (options.deviceName.empty() ? std::string("(the default)") : "'" + options.deviceName + "'") + ": " +
                (e.empty() ? std::string("no device") : e);
        return nullptr;
    }
    if (const char* model = a.getString(hd::kDeviceModelType)) d->model_ = model;
    if (const char* serial = a.getString(hd::kDeviceSerialNumber)) d->serial_ = serial;
    double value = 0;
    a.getDoublev(hd::kNominalMaxContinuousForce, &value);
    if (std::isfinite(value) && value > 0) d->maxForce_N_ = value;
    a.getDoublev(hd::kNominalMaxStiffness, &value);
    // The device reports N/mm: our coupling is in N/m.
    if (std::isfinite(value) && value > 0) d->maxStiffness_ = value * 1000;
    double box[6] = {0, 0, 0, 0, 0, 0};  // min x, y, z, max x, y, z in millimetres
    a.getDoublev(hd::kUsableWorkspaceDimensions, box);
    const Vec3 lo(box[0], box[1], box[2]), hi(box[3], box[4], box[5]);
    if (lo.allFinite() && hi.allFinite() && (hi.array() > lo.array()).all()) d->workspaceBox_ = geometry::Aabb{lo, hi};
    d->takeError();  // a runtime without the query leaves the box unknown: no automatic fit, not a failure
    hd::HDint rate = 0;
    a.getIntegerv(hd::kUpdateRate, &rate);
    if (rate > 0) d->rate_hz_ = rate;
    a.enable(hd::kForceOutput);
    a.enable(hd::kMaxForceClamping);  // the device's own clamp, behind ours
    if (const std::string e = d->takeError(); !e.empty()) {
        error = "OpenHaptics: cannot enable force output: " + e;
        return nullptr;
    }
    a.startScheduler();
    if (const std::string e = d->takeError(); !e.empty()) {
        error = "OpenHaptics: cannot start the servo loop: " + e;
        return nullptr;
    }
    d->schedulerRunning_ = true;

    // Calibration must be read inside the servo loop.
    struct Calibration {
        Api* api;
        hd::HDenum status = 0;
    } calibration{d->api_.get()};
    a.scheduleSynchronous(
        [](void* data) -> hd::HDCallbackCode {
            auto* c = static_cast<Calibration*>(data);
            c->status = c->api->checkCalibration();
            return hd::kCallbackDone;
        },
        &calibration, hd::kDefaultSchedulerPriority);
    if (calibration.status == hd::kCalibrationNeedsUpdate) {
        hd::HDint styles = 0;
        a.getIntegerv(hd::kCalibrationStyle, &styles);
        const hd::HDenum style = (styles & hd::kCalibrationAuto)      ? hd::kCalibrationAuto
                                 : (styles & hd::kCalibrationInkwell) ? hd::kCalibrationInkwell
                                                                      : hd::kCalibrationEncoderReset;
        a.updateCalibration(style);
    } else if (calibration.status == hd::kCalibrationNeedsManualInput && !options.allowUncalibrated) {
        error = "OpenHaptics: the " + (d->model_.empty() ? std::string("device") : d->model_) +
                " needs calibrating: put the stylus in its inkwell (or run the vendor's diagnostic tool) and try again";
        return nullptr;
    }
    if (const std::string e = d->takeError(); !e.empty()) {
        error = "OpenHaptics: calibration failed: " + e;
        return nullptr;
    }
    return d;
}

OpenHapticsDevice::~OpenHapticsDevice() {
    stopServo();
    if (api_ && device_ != hd::kInvalidHandle) {
        if (schedulerRunning_) api_->stopScheduler();
        api_->disableDevice(device_);
    }
}

hd::HDCallbackCode OpenHapticsDevice::servoCallback(void* self) {
    auto& d = *static_cast<OpenHapticsDevice*>(self);
    const Api& a = *d.api_;
    a.beginFrame(d.device_);
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0}, m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    hd::HDint buttons = 0;
    a.getDoublev(hd::kCurrentPosition, p);
    a.getDoublev(hd::kCurrentVelocity, v);
    a.getDoublev(hd::kCurrentTransform, m);
    a.getIntegerv(hd::kCurrentButtons, &buttons);
    hd::HDErrorInfo e = a.getError();
    if (e.errorCode != hd::kSuccess && !d.faulted_.load(std::memory_order_relaxed)) {
        d.faultCode_ = e.errorCode;
        d.faulted_.store(true, std::memory_order_release);
    }
    const bool faulted = d.faulted_.load(std::memory_order_relaxed);
    if (faulted) {
        // What a lost device reads as: the loop's watchdog zeroes the force and keeps it zero.
        const double nan = std::numeric_limits<double>::quiet_NaN();
        d.sample_.position_m = Vec3::Constant(nan);
        d.sample_.velocity_m_per_s = Vec3::Zero();
    } else {
        const WorkspaceTransform& w = d.options_.workspace;
        d.sample_.position_m = w.toScene(Vec3(p[0], p[1], p[2]));
        d.sample_.velocity_m_per_s = w.velocityToScene(Vec3(v[0], v[1], v[2]));
        Eigen::Matrix3d r;
        r << m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10];  // column-major, as OpenGL
        d.sample_.orientation = w.rotation * Eigen::Quaterniond(r).normalized();
        d.sample_.oriented = true;
        d.sample_.buttons = static_cast<std::uint32_t>(buttons);
    }
    const bool more = d.tick_ && !d.stopping_.load(std::memory_order_relaxed) && d.tick_();
    // The loop has clamped it; the device's own limit stands behind, and a fault or a stop sends nothing.
    const Vec3 f = (faulted || !more) ? Vec3::Zero() : d.options_.workspace.forceToDevice(d.force_N_);
    const double norm = f.norm();
    const Vec3 sent = norm > d.maxForce_N_ ? Vec3(f * (d.maxForce_N_ / norm)) : f;
    const double out[3] = {sent.x(), sent.y(), sent.z()};
    a.setDoublev(hd::kCurrentForce, out);
    a.endFrame(d.device_);
    e = a.getError();
    if (e.errorCode != hd::kSuccess && !d.faulted_.load(std::memory_order_relaxed)) {
        d.faultCode_ = e.errorCode;
        d.faulted_.store(true, std::memory_order_release);
    }
    if (more) return hd::kCallbackContinue;
    d.servoDone_.store(true, std::memory_order_release);
    return hd::kCallbackDone;
}

DeviceSample OpenHapticsDevice::read(double) { return sample_; }

void OpenHapticsDevice::commandForce(const Vec3& force_N) { force_N_ = force_N.allFinite() ? force_N : Vec3::Zero(); }

Status OpenHapticsDevice::startServo(std::function<bool()> tick) {
    stopServo();
    tick_ = std::move(tick);
    stopping_ = false;
    servoDone_ = false;
    callback_ = api_->scheduleAsynchronous(&OpenHapticsDevice::servoCallback, this, hd::kDefaultSchedulerPriority);
    if (const std::string e = takeError(); !e.empty()) {
        servoDone_ = true;
        return Error{{}, 0, "OpenHaptics: cannot schedule the haptic loop in the servo loop: " + e};
    }
    scheduled_ = true;
    return std::nullopt;
}

void OpenHapticsDevice::stopServo() {
    if (!scheduled_) return;
    stopping_ = true;
    // The next callback sends a zero force and returns done; wait for it (a servo tick is a millisecond)
    // so no callback is inside the loop's step once this returns, then make sure it is unscheduled.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    while (!servoDone_.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    api_->unschedule(callback_);
    scheduled_ = false;
    servoDone_ = true;
    takeError();
}

std::string OpenHapticsDevice::faultMessage() const {
    if (!faulted()) return {};
    char code[32];
    std::snprintf(code, sizeof code, " (HD error 0x%04x)", faultCode_);
    return std::string(hd::describeError(faultCode_)) + code;
}

}  // namespace hapticut::haptics
