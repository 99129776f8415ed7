// Rendering into a framebuffer object (multisampled, then resolved) and reading it back as an image.
#pragma once

#include <memory>
#include <string>

#include "render/image.h"

namespace hapticut::render {

class OffscreenTarget {
public:
    /// A width x height target with `samples` multisamples (clamped to what the driver offers).
    static std::unique_ptr<OffscreenTarget> create(int width, int height, int samples, std::string& error);
    ~OffscreenTarget();
    OffscreenTarget(const OffscreenTarget&) = delete;
    OffscreenTarget& operator=(const OffscreenTarget&) = delete;

    /// Later draws go into this target.
    void bind() const;
    /// Resolves the samples and reads the pixels, top row first; binds the window's framebuffer again.
    Image read() const;
    int width() const { return width_; }
    int height() const { return height_; }

private:
    OffscreenTarget() = default;
    int width_ = 0, height_ = 0;
    unsigned drawFbo_ = 0, resolveFbo_ = 0;
    unsigned colourRb_ = 0, depthRb_ = 0, resolveRb_ = 0;
};

/// Reads the window's back buffer (what the next swap shows), top row first.
Image readWindow(int width, int height);

}  // namespace hapticut::render
