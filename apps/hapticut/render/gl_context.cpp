// GLFW initialisation and the OpenGL 3.3 core context, with errors that say what to do.
#include "render/gl_context.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>

namespace hapticut::render {

namespace {

std::string lastGlfwError;
int openWindows = 0;

void onGlfwError(int, const char* description) { lastGlfwError = description ? description : "unknown GLFW error"; }

}  // namespace

std::unique_ptr<GlWindow> GlWindow::open(const WindowOptions& options, std::string& error) {
    glfwSetErrorCallback(onGlfwError);
    if (openWindows == 0 && !glfwInit()) {
        error = "cannot open a window: " + lastGlfwError;
        if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
            error +=
                " (no display here: run with a display, or under Xvfb: xvfb-run -a -s \"-screen 0 1920x1200x24\" "
                "hapticut ...)";
        return nullptr;
    }
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, options.samples);
    glfwWindowHint(GLFW_STEREO, options.quadStereo ? GLFW_TRUE : GLFW_FALSE);
    GLFWmonitor* monitor = options.fullscreen ? glfwGetPrimaryMonitor() : nullptr;
    int width = options.width, height = options.height;
    if (monitor) {
        if (const GLFWvidmode* mode = glfwGetVideoMode(monitor)) {
            width = mode->width;
            height = mode->height;
        }
    } else if (options.fitToMonitor) {
        if (GLFWmonitor* primary = glfwGetPrimaryMonitor()) {
            int x = 0, y = 0, areaWidth = 0, areaHeight = 0;
            glfwGetMonitorWorkarea(primary, &x, &y, &areaWidth, &areaHeight);
            // The title bar takes some of the height the work area offers.
            if (areaWidth > 0) width = std::min(width, areaWidth * 95 / 100);
            if (areaHeight > 0) height = std::min(height, areaHeight * 90 / 100);
        }
    }
    GLFWwindow* window = glfwCreateWindow(width, height, options.title.c_str(), monitor, nullptr);
    bool stereo = options.quadStereo;
    if (!window && options.quadStereo) {
        // Most consumer GL drivers offer no stereo visual: say so and carry on in mono.
        glfwWindowHint(GLFW_STEREO, GLFW_FALSE);
        window = glfwCreateWindow(width, height, options.title.c_str(), monitor, nullptr);
        stereo = false;
    }
    if (!window) {
        error = "cannot create an OpenGL 3.3 core window: " + lastGlfwError;
        if (openWindows == 0) glfwTerminate();
        return nullptr;
    }
    ++openWindows;
    glfwMakeContextCurrent(window);
    auto w = std::unique_ptr<GlWindow>(new GlWindow);
    w->window_ = window;
    GLboolean hasStereo = GL_FALSE;
    glGetBooleanv(GL_STEREO, &hasStereo);
    w->quadStereo_ = stereo && hasStereo == GL_TRUE;
    return w;
}

GlWindow::~GlWindow() {
    if (window_) glfwDestroyWindow(window_);
    if (--openWindows == 0) glfwTerminate();
}

std::string GlWindow::rendererDescription() const {
    const auto text = [](GLenum name) {
        const GLubyte* s = glGetString(name);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    return text(GL_VERSION) + ", " + text(GL_RENDERER);
}

}  // namespace hapticut::render
