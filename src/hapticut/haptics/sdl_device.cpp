// SDL2 joysticks as haptic devices.
#include "hapticut/haptics/sdl_device.h"

#include <SDL.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace hapticut::haptics {

namespace {

/// Joystick and haptic subsystems, reference-counted by SDL itself; without video, SDL needs no display.
bool initSdl(std::string& error) {
    SDL_SetHint(SDL_HINT_JOYSTICK_ALLOW_BACKGROUND_EVENTS, "1");  // a device works without a focused window
    if (SDL_InitSubSystem(SDL_INIT_JOYSTICK) != 0) {
        error = std::string("SDL: joystick support does not start: ") + SDL_GetError();
        return false;
    }
    SDL_InitSubSystem(SDL_INIT_HAPTIC);  // force feedback is optional: without it, rumble or nothing
    return true;
}

void quitSdl() {
    if (SDL_WasInit(SDL_INIT_HAPTIC)) SDL_QuitSubSystem(SDL_INIT_HAPTIC);
    SDL_QuitSubSystem(SDL_INIT_JOYSTICK);
}

SdlJoystickInfo describe(int index, SDL_Joystick* joystick, SDL_Haptic* haptic) {
    SdlJoystickInfo info;
    info.index = index;
    if (const char* name = SDL_JoystickName(joystick)) info.name = name;
    info.axes = SDL_JoystickNumAxes(joystick);
    info.buttons = SDL_JoystickNumButtons(joystick);
    info.constantForce = haptic && (SDL_HapticQuery(haptic) & SDL_HAPTIC_CONSTANT);
    info.rumble = SDL_JoystickHasRumble(joystick) == SDL_TRUE;
    return info;
}

std::string joystickList() {
    const int count = SDL_NumJoysticks();
    if (count <= 0)
        return "SDL sees no joystick (is it plugged in, and may this user read /dev/input/event*? On Debian: add "
               "yourself to the 'input' group)";
    std::string text = "SDL sees " + std::to_string(count) + ":";
    for (int i = 0; i < count; ++i) {
        const char* name = SDL_JoystickNameForIndex(i);
        text += " " + std::to_string(i) + " '" + (name ? name : "unnamed") + "'";
    }
    return text;
}

}  // namespace

/// SDL's handles, touched only by the device's own thread.
struct SdlDevice::Sdl {
    SDL_Joystick* joystick = nullptr;
    SDL_Haptic* haptic = nullptr;
    int effect = -1;
};

Result<std::vector<SdlJoystickInfo>, Error> SdlDevice::list() {
    std::vector<SdlJoystickInfo> found;
    if (std::string error; !initSdl(error)) return unexpected(Error{{}, 0, error});
    for (int i = 0; i < SDL_NumJoysticks(); ++i) {
        SDL_Joystick* joystick = SDL_JoystickOpen(i);
        if (!joystick) continue;
        SDL_Haptic* haptic = SDL_JoystickIsHaptic(joystick) == 1 ? SDL_HapticOpenFromJoystick(joystick) : nullptr;
        found.push_back(describe(i, joystick, haptic));
        if (haptic) SDL_HapticClose(haptic);
        SDL_JoystickClose(joystick);
    }
    quitSdl();
    return found;
}

Result<std::unique_ptr<SdlDevice>, Error> SdlDevice::open(const SdlOptions& options) {
    auto d = std::unique_ptr<SdlDevice>(new SdlDevice);
    d->options_ = options;
    d->sdl_ = std::make_unique<Sdl>();
    // SDL is opened, polled and closed on the device's thread; wait until it says how opening went.
    std::atomic<int> started{0};  // 0: opening, 1: running, -1: failed
    std::string threadError;
    d->thread_ = std::thread([&, self = d.get()] { self->threadMain(&threadError, &started); });
    while (started.load(std::memory_order_acquire) == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (started.load() < 0) {
        d->thread_.join();
        return unexpected(Error{{}, 0, threadError});
    }
    return d;
}

SdlDevice::~SdlDevice() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

std::string_view SdlDevice::feedback() const {
    return info_.constantForce ? "constant force" : info_.rumble ? "rumble" : "none";
}

DeviceSample SdlDevice::read(double) {
    const Input& in = input_.readLatest();
    DeviceSample s;
    if (lost()) {
        s.position_m = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
        return s;
    }
    s.position_m = options_.workspace.toScene(in.position);
    s.velocity_m_per_s = options_.workspace.velocityToScene(in.velocity);
    s.buttons = in.buttons;
    return s;
}

void SdlDevice::commandForce(const Vec3& force_N) {
    const Vec3 f = force_N.allFinite() ? force_N : Vec3::Zero();
    fx_.store(f.x(), std::memory_order_relaxed);
    fy_.store(f.y(), std::memory_order_relaxed);
    fz_.store(f.z(), std::memory_order_relaxed);
}

void SdlDevice::threadMain(std::string* error, std::atomic<int>* started) {
    // SDL keeps per-thread data (its error message) for threads it did not create, and frees it only
    // when asked: last thing on every way out of this thread, after SDL_Quit.
    struct ThreadDataCleanup {
        ~ThreadDataCleanup() { SDL_TLSCleanup(); }
    } threadDataCleanup;
    Sdl& sdl = *sdl_;
    {
        std::string e;
        if (!initSdl(e)) {
            *error = e;
            started->store(-1, std::memory_order_release);
            return;
        }
        const int count = SDL_NumJoysticks();
        if (options_.index < 0 || options_.index >= count) {
            *error = "SDL: no joystick " + std::to_string(options_.index) + ": " + joystickList();
            quitSdl();
            started->store(-1, std::memory_order_release);
            return;
        }
        sdl.joystick = SDL_JoystickOpen(options_.index);
        if (!sdl.joystick) {
            *error = "SDL: cannot open joystick " + std::to_string(options_.index) + ": " + SDL_GetError();
            quitSdl();
            started->store(-1, std::memory_order_release);
            return;
        }
        if (SDL_JoystickIsHaptic(sdl.joystick) == 1) sdl.haptic = SDL_HapticOpenFromJoystick(sdl.joystick);
        info_ = describe(options_.index, sdl.joystick, sdl.haptic);
        if (info_.constantForce) {
            SDL_HapticEffect effect{};
            effect.type = SDL_HAPTIC_CONSTANT;
            effect.constant.direction.type = SDL_HAPTIC_CARTESIAN;
            effect.constant.length = SDL_HAPTIC_INFINITY;
            effect.constant.level = 0;
            sdl.effect = SDL_HapticNewEffect(sdl.haptic, &effect);
            if (sdl.effect < 0 || SDL_HapticRunEffect(sdl.haptic, sdl.effect, 1) != 0) info_.constantForce = false;
        }
        SDL_JoystickEventState(SDL_IGNORE);  // polled below; no event queue to fill
    }
    started->store(1, std::memory_order_release);

    using Clock = std::chrono::steady_clock;
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1 / std::max(options_.pollRate_hz, 1.0)));
    const auto effectPeriod = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1 / std::max(options_.effectRate_hz, 1.0)));
    auto next = Clock::now(), nextEffect = next, last = next;
    Vec3 position = Vec3::Zero();
    double lastStrength = -1;
    while (!stop_.load(std::memory_order_relaxed)) {
        SDL_JoystickUpdate();
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        if (SDL_JoystickGetAttached(sdl.joystick) != SDL_TRUE) {
            lost_.store(true, std::memory_order_release);  // unplugged: the watchdog stops the loop's forces
            break;
        }
        Vec3 deflection = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            const int axis = options_.axes[static_cast<std::size_t>(k)];
            if (axis < 0 || axis >= info_.axes) continue;
            double v = std::clamp(SDL_JoystickGetAxis(sdl.joystick, axis) / 32767.0, -1.0, 1.0);
            if (options_.invert[static_cast<std::size_t>(k)]) v = -v;
            // Rescale past the dead zone so that small deflections start from zero, not with a jump.
            const double a = std::abs(v);
            deflection[k] =
                a <= options_.deadZone ? 0 : std::copysign((a - options_.deadZone) / (1 - options_.deadZone), v);
        }
        const Vec3 previous = position;
        if (options_.control == SdlControl::Position)
            position = deflection;
        else
            position = (position + deflection * (options_.rate_per_s * dt))
                           .cwiseMax(Vec3::Constant(-1))
                           .cwiseMin(Vec3::Constant(1));
        Input& in = input_.writeSlot();
        in.position = position;
        in.velocity = dt > 0 ? Vec3((position - previous) / dt) : Vec3::Zero();
        in.buttons = 0;
        for (int b = 0; b < std::min(info_.buttons, 32); ++b)
            if (SDL_JoystickGetButton(sdl.joystick, b)) in.buttons |= 1u << b;
        input_.publish();
        polls_.fetch_add(1, std::memory_order_relaxed);

        if (now >= nextEffect) {
            nextEffect = now + effectPeriod;
            // The force in the device's frame: x right, y up, z toward the user. A stick moves in x and
            // z; SDL's direction is where the force comes from, in x right and y toward the user.
            const Vec3 f = options_.workspace.forceToDevice(Vec3(fx_.load(std::memory_order_relaxed),
                                                                 fy_.load(std::memory_order_relaxed),
                                                                 fz_.load(std::memory_order_relaxed)));
            const double strength = std::clamp(f.norm() / std::max(options_.maxForce_N, 1e-9), 0.0, 1.0);
            if (info_.constantForce) {
                const double planar = std::hypot(f.x(), f.z());
                SDL_HapticEffect effect{};
                effect.type = SDL_HAPTIC_CONSTANT;
                effect.constant.direction.type = SDL_HAPTIC_CARTESIAN;
                effect.constant.direction.dir[0] = planar > 0 ? static_cast<Sint32>(-f.x() / planar * 10000) : 0;
                effect.constant.direction.dir[1] = planar > 0 ? static_cast<Sint32>(-f.z() / planar * 10000) : 0;
                effect.constant.length = SDL_HAPTIC_INFINITY;
                effect.constant.level =
                    static_cast<Sint16>(std::clamp(planar / std::max(options_.maxForce_N, 1e-9), 0.0, 1.0) * 32767);
                SDL_HapticUpdateEffect(sdl.haptic, sdl.effect, &effect);
            } else if (info_.rumble && (strength > 0 || lastStrength != 0)) {
                // Renewed every effect period, lasting two: stops on its own if this thread does.
                const auto level = static_cast<Uint16>(strength * 65535);
                SDL_JoystickRumble(sdl.joystick, level, level,
                                   static_cast<Uint32>(2000 / std::max(options_.effectRate_hz, 1.0)));
            }
            played_.store(strength, std::memory_order_relaxed);
            lastStrength = strength;
        }
        next += period;
        if (Clock::now() > next + 10 * period) next = Clock::now();
        std::this_thread::sleep_until(next);
    }

    // Zero force before letting go.
    if (sdl.haptic) {
        if (sdl.effect >= 0) {
            SDL_HapticStopEffect(sdl.haptic, sdl.effect);
            SDL_HapticDestroyEffect(sdl.haptic, sdl.effect);
        }
        SDL_HapticClose(sdl.haptic);
    }
    if (info_.rumble && SDL_JoystickGetAttached(sdl.joystick) == SDL_TRUE) SDL_JoystickRumble(sdl.joystick, 0, 0, 0);
    played_.store(0, std::memory_order_relaxed);
    SDL_JoystickClose(sdl.joystick);
    quitSdl();
}

}  // namespace hapticut::haptics
