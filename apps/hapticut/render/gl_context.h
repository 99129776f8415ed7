// An OpenGL 3.3 core context in a GLFW window: visible for the viewer, hidden for offscreen screenshots.
#pragma once

#include <memory>
#include <string>

struct GLFWwindow;

namespace hapticut::render {

struct WindowOptions {
    int width = 1280, height = 1024;
    bool visible = true;
    bool fullscreen = false;  // on the primary monitor, at its current mode
    /// Shrink the window to fit the primary monitor's work area (less the desktop's bars), so that an
    /// ordinary 1366x768 screen shows all of it; off when the user asked for a size.
    bool fitToMonitor = false;
    bool quadStereo = false;  // ask for a stereo (quad-buffer) framebuffer
    int samples = 4;          // multisampling of the window's own framebuffer
    std::string title = "Hapticut";
};

class GlWindow {
public:
    /// Opens the window and makes its context current; on failure nothing, with `error` saying why
    /// (no display, no OpenGL 3.3) and what to do.
    static std::unique_ptr<GlWindow> open(const WindowOptions& options, std::string& error);
    ~GlWindow();
    GlWindow(const GlWindow&) = delete;
    GlWindow& operator=(const GlWindow&) = delete;

    GLFWwindow* handle() const { return window_; }
    /// Whether the framebuffer really has left and right back buffers (asked for and granted).
    bool hasQuadStereo() const { return quadStereo_; }
    /// "4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)": what renders.
    std::string rendererDescription() const;

private:
    GlWindow() = default;
    GLFWwindow* window_ = nullptr;
    bool quadStereo_ = false;
};

}  // namespace hapticut::render
