// A Phantom / Touch through OpenHaptics' HD API, opened at run time: any build can drive one when the
// vendor runtime is installed, and says precisely what is missing when it is not (SPEC R6).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/haptics/device.h"
#include "hapticut/haptics/hd_api.h"
#include "hapticut/haptics/shared_library.h"

namespace hapticut::haptics {

struct OpenHapticsOptions {
    std::string deviceName;  // a configured device's name; empty: the default device
    /// Library file names tried in order. Default: $HAPTICUT_HD_LIBRARY if set, else the HD runtime's
    /// names on this platform (libHD.so and its versions; HD.dll on Windows).
    std::vector<std::string> libraryNames;
    /// Folders searched, in order; "" is the system's own search. Default: the system search, then the
    /// folders the OpenHaptics installers use.
    std::vector<std::string> searchFolders;
    /// Device millimetres to scene metres: 1 mm = 1 mm by default, the device's origin at the scene's.
    WorkspaceTransform workspace{0.001};
    /// Run even if the device asks for manual calibration (positions may be offset).
    bool allowUncalibrated = false;
};

std::vector<std::string> defaultHdLibraryNames();
std::vector<std::string> defaultHdSearchFolders();

class OpenHapticsDevice final : public Device, public ServoClock {
public:
    /// Opens the library, resolves the functions, initialises and calibrates the device, enables force
    /// output; an error saying what is missing and what to do.
    static Result<std::unique_ptr<OpenHapticsDevice>, Error> open(const OpenHapticsOptions& options);
    /// Whether the HD library can be opened and has every function, without touching a device: its
    /// path, or an error saying why not.
    static Result<std::string, Error> probeLibrary(const OpenHapticsOptions& options);
    ~OpenHapticsDevice() override;

    std::string_view name() const override { return "openhaptics"; }
    DeviceSample read(double time_s) override;
    void commandForce(const Vec3& force_N) override;
    double maxForce_N() const override { return maxForce_N_; }
    WorkspaceTransform workspace() const override { return options_.workspace; }
    std::optional<geometry::Aabb> workspaceBox() const override { return workspaceBox_; }
    bool setWorkspace(const WorkspaceTransform& workspace) override {
        options_.workspace = workspace;
        return true;
    }
    ServoClock* servoClock() override { return this; }

    Status startServo(std::function<bool()> tick) override;
    void stopServo() override;
    double servoRate_hz() const override { return rate_hz_; }

    /// "PHANTOM Omni", "Touch", ...; its serial number; the library that was opened.
    const std::string& model() const { return model_; }
    const std::string& serial() const { return serial_; }
    const std::string& libraryPath() const { return library_->path(); }
    /// The device's nominal maximum stiffness (N/m): the loop keeps the coupling below it.
    double maxStiffness_N_per_m() const override {
        return maxStiffness_ > 0 ? maxStiffness_ : Device::maxStiffness_N_per_m();
    }
    /// Set when the device reported an error in the servo loop (a lost connection, overheated motors):
    /// from then on it reads as non-finite, which trips the loop's watchdog, and sends no force.
    bool faulted() const { return faulted_.load(std::memory_order_acquire); }
    std::string faultMessage() const;

private:
    static std::unique_ptr<OpenHapticsDevice> openOrExplain(const OpenHapticsOptions& options, std::string& error);
    struct Api;
    OpenHapticsDevice() = default;
    static hd::HDCallbackCode servoCallback(void* self);
    /// Opens the library and resolves every function; false with `error` naming what is missing.
    bool load(std::string& error);
    /// The first pending HD error as "what happened (code 0x0302, internal 5)", or empty.
    std::string takeError();

    OpenHapticsOptions options_;
    std::unique_ptr<SharedLibrary> library_;
    std::unique_ptr<Api> api_;
    hd::HHD device_ = hd::kInvalidHandle;
    hd::HDSchedulerHandle callback_ = 0;
    bool scheduled_ = false, schedulerRunning_ = false;
    std::string model_, serial_;
    double maxForce_N_ = kDefaultMaxForce_N, maxStiffness_ = 0, rate_hz_ = 1000;
    std::optional<geometry::Aabb> workspaceBox_;  // the usable workspace, device millimetres
    std::function<bool()> tick_;
    std::atomic<bool> stopping_{false}, faulted_{false}, servoDone_{true};
    hd::HDerror faultCode_ = 0;  // written by the servo thread before faulted_ is set
    // Owned by the servo thread: the frame's state, and the force the loop commanded in it.
    DeviceSample sample_;
    Vec3 force_N_ = Vec3::Zero();
};

}  // namespace hapticut::haptics
