// The subset of OpenHaptics' HD API that Hapticut uses, declared from its documented ABI so that no SDK
// is needed at build time: the library is opened at run time (openhaptics_device.h) and these types
// and values must match the vendor's headers (hdDefines.h, hdDevice.h, hdScheduler.h).
#pragma once

namespace hapticut::haptics::hd {

using HHD = unsigned int;
using HDenum = unsigned int;
using HDerror = unsigned int;
using HDint = int;
using HDdouble = double;
using HDushort = unsigned short;
using HDstring = const char*;
using HDCallbackCode = unsigned int;
using HDSchedulerHandle = unsigned long;
using HDSchedulerCallback = HDCallbackCode (*)(void* userData);

struct HDErrorInfo {
    HDerror errorCode;
    int internalErrorCode;
    HHD hHD;
};

inline constexpr HHD kInvalidHandle = 0xFFFFFFFFu;
inline constexpr HDCallbackCode kCallbackDone = 0, kCallbackContinue = 1;
inline constexpr HDushort kDefaultSchedulerPriority = 0xFFFF / 2;

// Errors.
inline constexpr HDerror kSuccess = 0x0000;
inline constexpr HDerror kWarmMotors = 0x0200, kExceededMaxForce = 0x0201, kExceededMaxForceImpulse = 0x0202,
                         kExceededMaxVelocity = 0x0203, kForceError = 0x0204;
inline constexpr HDerror kDeviceFault = 0x0300, kDeviceAlreadyInitiated = 0x0301, kCommError = 0x0302,
                         kCommConfigError = 0x0303, kTimerError = 0x0304;
inline constexpr HDerror kInvalidLicense = 0x0600;

// Parameters.
inline constexpr HDenum kCurrentButtons = 0x2000;
inline constexpr HDenum kCurrentPosition = 0x2050, kCurrentVelocity = 0x2051, kCurrentTransform = 0x2052;
inline constexpr HDenum kDeviceModelType = 0x2501, kDeviceSerialNumber = 0x2504;
inline constexpr HDenum kUsableWorkspaceDimensions = 0x2551;
inline constexpr HDenum kUpdateRate = 0x2600, kNominalMaxStiffness = 0x2602, kNominalMaxForce = 0x2603,
                        kNominalMaxContinuousForce = 0x2604;
inline constexpr HDenum kCurrentForce = 0x2700;
inline constexpr HDenum kForceOutput = 0x4000, kMaxForceClamping = 0x4001;

// Calibration.
inline constexpr HDenum kCalibrationOk = 0x5000, kCalibrationNeedsUpdate = 0x5001,
                        kCalibrationNeedsManualInput = 0x5002;
inline constexpr HDint kCalibrationStyle = 0x2555;
inline constexpr HDint kCalibrationEncoderReset = 1 << 0, kCalibrationAuto = 1 << 1, kCalibrationInkwell = 1 << 2;

/// A plain-words reading of an HD error code, for messages a user can act on.
const char* describeError(HDerror code);

}  // namespace hapticut::haptics::hd
