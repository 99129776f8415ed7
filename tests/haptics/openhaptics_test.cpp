// The OpenHaptics backend against an emulation of the HD API (tests/haptics/hd_emulation), loaded
// through the same dlopen path as the vendor's library: loading errors, calibration, the servo loop
// driving the haptic loop at its rate, force clamping, a device lost mid-run, a clean shutdown.
#include <gtest/gtest.h>

#include <atomic>

#include <dlfcn.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/material.h"
#include "test_support.h"

namespace hapticut::haptics {
namespace {

/// The device, or nothing with `error` holding the message.
std::unique_ptr<OpenHapticsDevice> openOrSay(const OpenHapticsOptions& options, std::string& error) {
    return test::valueOrMessage(OpenHapticsDevice::open(options), error);
}

/// The emulation's test controls, resolved from the same library the backend opens.
struct Emulator {
    void* handle = dlopen(HD_EMULATION_LIBRARY, RTLD_NOW);
    template <class F>
    F get(const char* name) const {
        return reinterpret_cast<F>(dlsym(handle, name));
    }
    void reset() const { get<void (*)()>("hdEmu_reset")(); }
    void setPosition(double x, double y, double z) const {
        get<void (*)(double, double, double)>("hdEmu_setPosition")(x, y, z);
    }
    void setCalibration(unsigned s) const { get<void (*)(unsigned)>("hdEmu_setCalibration")(s); }
    void failInit(unsigned code) const { get<void (*)(unsigned)>("hdEmu_failInit")(code); }
    void failAfterTicks(long ticks, unsigned code) const {
        get<void (*)(long, unsigned)>("hdEmu_failAfterTicks")(ticks, code);
    }
    Vec3 lastForce() const {
        double f[3];
        get<void (*)(double*)>("hdEmu_lastForce")(f);
        return {f[0], f[1], f[2]};
    }
    double maxForceSent() const { return get<double (*)()>("hdEmu_maxForceSent")(); }
    long ticks() const { return get<long (*)()>("hdEmu_ticks")(); }
    long ticksWithCallbacks() const { return get<long (*)()>("hdEmu_ticksWithCallbacks")(); }
    void stallScheduler(long ms) const { get<void (*)(long)>("hdEmu_stallScheduler")(ms); }
    long calibrationUpdates() const { return get<long (*)()>("hdEmu_calibrationUpdates")(); }
    long frameErrors() const { return get<long (*)()>("hdEmu_frameErrors")(); }
    bool deviceOpen() const { return get<int (*)()>("hdEmu_deviceOpen")(); }
    bool forceOutput() const { return get<int (*)()>("hdEmu_forceOutput")(); }
    bool schedulerRunning() const { return get<int (*)()>("hdEmu_schedulerRunning")(); }
};

class OpenHaptics : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_NE(emu.handle, nullptr) << dlerror();
        emu.reset();
    }
    void TearDown() override { emu.reset(); }

    static OpenHapticsOptions emulated() {
        OpenHapticsOptions o;
        o.libraryNames = {std::filesystem::path(HD_EMULATION_LIBRARY).filename().string()};
        o.searchFolders = {std::filesystem::path(HD_EMULATION_LIBRARY).parent_path().string()};
        return o;
    }

    /// The emulated stylus `depth_mm` inside the front of the heart (device millimetres, scene metres at
    /// 1:1000), and the device opened on it.
    std::unique_ptr<OpenHapticsDevice> pressing(const Vec3& front, double depth_mm) const {
        emu.setPosition(front.x() * 1e3, front.y() * 1e3, front.z() * 1e3 - depth_mm);
        std::string error;
        auto device = openOrSay(emulated(), error);
        EXPECT_TRUE(device) << error;
        return device;
    }

    Emulator emu;
};

TEST_F(OpenHaptics, AMissingLibrarySaysWhereItLookedAndWhatToInstall) {
    OpenHapticsOptions o;
    o.libraryNames = {"libHD-not-here.so"};
    o.searchFolders = {"/nonexistent/openhaptics/lib", ""};
    std::string error;
    EXPECT_FALSE(openOrSay(o, error));
    EXPECT_NE(error.find("could not open libHD-not-here.so"), std::string::npos) << error;
    EXPECT_NE(error.find("\n  /nonexistent/openhaptics/lib"), std::string::npos) << error;
    EXPECT_NE(error.find("\n  the system search path"), std::string::npos) << error;
    EXPECT_NE(error.find("Install the OpenHaptics runtime"), std::string::npos) << error;
    EXPECT_NE(error.find("HAPTICUT_HD_LIBRARY"), std::string::npos) << error;
}

TEST_F(OpenHaptics, AFileThatIsNotALibrarySaysWhyItWouldNotLoad) {
    const auto folder = std::filesystem::temp_directory_path() / ("hapticut-hd-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    { std::ofstream(folder / "libHD.so") << "not an ELF file"; }
    OpenHapticsOptions o;
    o.libraryNames = {"libHD.so"};
    o.searchFolders = {folder.string()};
    std::string error;
    EXPECT_FALSE(openOrSay(o, error));
    std::filesystem::remove_all(folder);
    EXPECT_NE(error.find("found but could not load"), std::string::npos) << error;
    EXPECT_NE(error.find((folder / "libHD.so").string()), std::string::npos) << error;
}

TEST_F(OpenHaptics, ALibraryWithoutAFunctionNamesIt) {
    OpenHapticsOptions o;
    o.libraryNames = {std::filesystem::path(HD_EMULATION_INCOMPLETE_LIBRARY).filename().string()};
    o.searchFolders = {std::filesystem::path(HD_EMULATION_INCOMPLETE_LIBRARY).parent_path().string()};
    std::string error;
    EXPECT_FALSE(openOrSay(o, error));
    EXPECT_NE(error.find("lacks hdUpdateCalibration"), std::string::npos) << error;
}

TEST_F(OpenHaptics, ADeviceThatWillNotOpenSaysWhyInPlainWords) {
    emu.failInit(hd::kCommError);
    std::string error;
    EXPECT_FALSE(openOrSay(emulated(), error));
    EXPECT_NE(error.find("plugged in and powered"), std::string::npos) << error;
    EXPECT_NE(error.find("0x0302"), std::string::npos) << error;
    EXPECT_NE(error.find("emulated communication error"), std::string::npos) << error;
}

TEST_F(OpenHaptics, CalibrationIsUpdatedWhenItCanBeAndRefusedWhenItNeedsTheInkwell) {
    std::string error;
    emu.setCalibration(hd::kCalibrationNeedsUpdate);
    {
        auto device = openOrSay(emulated(), error);
        ASSERT_TRUE(device) << error;
        EXPECT_EQ(emu.calibrationUpdates(), 1);
        EXPECT_EQ(device->model(), "Emulated Touch");
        EXPECT_EQ(device->serial(), "EMU-0001");
        EXPECT_DOUBLE_EQ(device->maxForce_N(), 0.9);            // the nominal continuous force
        EXPECT_DOUBLE_EQ(device->maxStiffness_N_per_m(), 800);  // 0.8 N/mm
        EXPECT_TRUE(emu.forceOutput());
    }
    EXPECT_FALSE(emu.deviceOpen()) << "the device was not released";
    EXPECT_FALSE(emu.schedulerRunning());
    emu.setCalibration(hd::kCalibrationNeedsManualInput);
    EXPECT_FALSE(openOrSay(emulated(), error));
    EXPECT_NE(error.find("inkwell"), std::string::npos) << error;
    EXPECT_FALSE(emu.deviceOpen());
    OpenHapticsOptions anyway = emulated();
    anyway.allowUncalibrated = true;
    EXPECT_TRUE(openOrSay(anyway, error)) << error;
}

struct Heart {
    mesh::SurfaceMesh mesh = mesh::procedural::makeHeart({});
    cutting::CutModel organ{mesh, physics::buildModel(mesh, physics::Material{})};
    physics::MassSpringModel& model = organ.model();
    Vec3 front() const {
        Vec3 best = mesh.positions[0];
        for (const Vec3& p : mesh.positions)
            if (std::abs(p.x()) < 0.01 && std::abs(p.y()) < 0.01 && p.z() > best.z()) best = p;
        return best;
    }
};

TEST_F(OpenHaptics, TheServoLoopDrivesTheHapticLoopAtItsRateAndTheForceIsClamped) {
    Heart h;
    const Vec3 front = h.front();
    auto device = pressing(front, 8);
    ASSERT_TRUE(device);
    std::string error;
    LoopConfig config;
    config.rampTime_s = 0.05;
    {
        HapticLoop loop(h.organ, *device, config);
        RealTimeScheduler clock(loop);
        const long ticks0 = emu.ticksWithCallbacks();
        const auto started = std::chrono::steady_clock::now();
        ASSERT_FALSE(clock.start());
        // 400 ms, and on until the press has built up (within them in a release build; a sanitizer's
        // slower steps, beside other tests, stall the loop and each stall ramps the force in again), at
        // most two seconds.
        std::this_thread::sleep_for(std::chrono::milliseconds(400));
        while (emu.maxForceSent() <= 0.8 && std::chrono::steady_clock::now() - started < std::chrono::seconds(2))
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        const Snapshot& s = loop.snapshots().readLatest();
        EXPECT_TRUE(s.hands[0].device_m.isApprox(Vec3(front.x(), front.y(), front.z() - 0.008), 1e-9))
            << s.hands[0].device_m.transpose();
        clock.stop();
        const double ran_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
        const long ticks = emu.ticksWithCallbacks() - ticks0;
        // One loop step per servo tick that ran the scheduled callbacks: the servo's clock is the
        // loop's. (Counting every tick instead would count those before the scheduler hooks in, which
        // a loaded machine makes many.) A tick at each end may run the device's callbacks without a step.
        EXPECT_NEAR(static_cast<double>(loop.stats().steps), static_cast<double>(ticks), 2);
        // At 1 kHz, on a machine that may be running other tests.
        EXPECT_GT(loop.stats().steps, 200);
        EXPECT_LT(static_cast<double>(loop.stats().steps), 1.1 * ran_ms + 10);
        // 8 mm through a 400 N/m coupling is 3.2 N: clamped to the device's 0.9 N.
        EXPECT_GT(emu.maxForceSent(), 0.8);
        EXPECT_LE(emu.maxForceSent(), 0.9 + 1e-9);
        EXPECT_EQ(emu.lastForce(), Vec3::Zero()) << "stopping must leave the device at zero force";
    }
    EXPECT_EQ(emu.frameErrors(), 0) << "every force must be set inside a begin/end frame";
}

TEST_F(OpenHaptics, ADeviceLostMidRunTripsTheWatchdogAndSendsNoForce) {
    Heart h;
    auto device = pressing(h.front(), 3);
    ASSERT_TRUE(device);
    std::string error;
    LoopConfig config;
    config.rampTime_s = 0.02;
    HapticLoop loop(h.organ, *device, config);
    RealTimeScheduler clock(loop);
    ASSERT_FALSE(clock.start());
    // Until the press has built up (150 ms in a release build; a sanitizer's slower steps stall the
    // loop, and each stall ramps the force in again), at most two seconds.
    const auto pressStart = std::chrono::steady_clock::now();
    while (emu.lastForce().norm() <= 0.1 && std::chrono::steady_clock::now() - pressStart < std::chrono::seconds(2))
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_GT(emu.lastForce().norm(), 0.1) << "pressing 3 mm in before the loss";
    emu.failAfterTicks(10, hd::kCommError);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    EXPECT_TRUE(device->faulted());
    EXPECT_NE(device->faultMessage().find("communication with the device failed"), std::string::npos)
        << device->faultMessage();
    EXPECT_TRUE(loop.snapshots().readLatest().watchdogTripped);
    EXPECT_EQ(emu.lastForce(), Vec3::Zero());
    clock.stop();
}

// The device's servo scheduler held up for 100 ms (a Touch's driver stalled, the process stopped): the
// loop that its ticks drive missed about a hundred periods. They count as overruns, the watchdog zeroes
// the first force after the gap, and the force ramps back in.
TEST_F(OpenHaptics, AStalledServoTickCountsAsOverrunsAndTheForceRampsBackIn) {
    Heart h;
    auto device = pressing(h.front(), 2);
    ASSERT_TRUE(device);
    LoopConfig config;
    config.rampTime_s = 0.05;
    config.stallRampTime_s = 0.05;
    HapticLoop loop(h.organ, *device, config);
    constexpr std::size_t kSteps = 4000;
    std::vector<double> force(kSteps, -1), wall_ms(kSteps, 0);
    const auto begin = std::chrono::steady_clock::now();
    std::atomic<long> steps{0};
    RealTimeScheduler clock(loop);
    ASSERT_FALSE(clock.start(static_cast<long>(kSteps), [&](const StepOutput& s) {
        const auto i = static_cast<std::size_t>(steps.load(std::memory_order_relaxed));
        force[i] = s.hand().force_N.norm();
        wall_ms[i] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
        steps.store(static_cast<long>(i) + 1, std::memory_order_release);
    }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    emu.stallScheduler(100);
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    clock.stop();
    const long n = steps.load(std::memory_order_acquire);
    // The gap: the longest time between two steps.
    long after = 1;
    for (long i = 2; i < n; ++i)
        if (wall_ms[static_cast<std::size_t>(i)] - wall_ms[static_cast<std::size_t>(i - 1)] >
            wall_ms[static_cast<std::size_t>(after)] - wall_ms[static_cast<std::size_t>(after - 1)])
            after = i;
    const auto a = static_cast<std::size_t>(after);
    ASSERT_GT(wall_ms[a] - wall_ms[a - 1], 95) << "the scheduler stalled";
    ASSERT_LT(a + 60, static_cast<std::size_t>(n));
    const LoopStats& st = loop.stats();
    EXPECT_GE(st.stalls, 1);
    EXPECT_GE(st.missedPeriods, 95);
    EXPECT_GE(st.overruns, st.missedPeriods) << "every missed period is an overrun";
    EXPECT_GT(st.periodError_us.summary().max, 95'000.0);
    EXPECT_EQ(force[a], 0.0) << "the first step after the gap sends no force";
    // The ramp's shape, when this was the run's only stall (a sanitizer's build may stall more often).
    if (st.stalls == 1) {
        EXPECT_GT(force[a - 1], 0.3) << "pressing before the stall";
        EXPECT_LT(force[a + 10], 0.5 * force[a - 1]) << "the force ramps back in";
        EXPECT_NEAR(force[a + 60], force[a - 1], 0.15 * force[a - 1]) << "to the press it had";
    }
}

}  // namespace
}  // namespace hapticut::haptics
