// Framebuffer objects for screenshots: draw multisampled, blit to a plain buffer, read back.
#include "render/offscreen.h"

#include <epoxy/gl.h>

#include <algorithm>

namespace hapticut::render {

std::unique_ptr<OffscreenTarget> OffscreenTarget::create(int width, int height, int samples, std::string& error) {
    GLint maxSize = 0, maxSamples = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    if (width <= 0 || height <= 0 || width > maxSize || height > maxSize) {
        error = "cannot render " + std::to_string(width) + "x" + std::to_string(height) + ": the driver allows 1 to " +
                std::to_string(maxSize) + " pixels a side";
        return nullptr;
    }
    auto t = std::unique_ptr<OffscreenTarget>(new OffscreenTarget);
    t->width_ = width;
    t->height_ = height;
    samples = std::clamp(samples, 0, static_cast<int>(maxSamples));
    glGenFramebuffers(1, &t->drawFbo_);
    glGenRenderbuffers(1, &t->colourRb_);
    glGenRenderbuffers(1, &t->depthRb_);
    glBindFramebuffer(GL_FRAMEBUFFER, t->drawFbo_);
    glBindRenderbuffer(GL_RENDERBUFFER, t->colourRb_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->colourRb_);
    glBindRenderbuffer(GL_RENDERBUFFER, t->depthRb_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depthRb_);
    const GLenum drawStatus = glCheckFramebufferStatus(GL_FRAMEBUFFER);

    glGenFramebuffers(1, &t->resolveFbo_);
    glGenRenderbuffers(1, &t->resolveRb_);
    glBindFramebuffer(GL_FRAMEBUFFER, t->resolveFbo_);
    glBindRenderbuffer(GL_RENDERBUFFER, t->resolveRb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->resolveRb_);
    const GLenum resolveStatus = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (drawStatus != GL_FRAMEBUFFER_COMPLETE || resolveStatus != GL_FRAMEBUFFER_COMPLETE) {
        error = "the offscreen framebuffer is incomplete (status " + std::to_string(drawStatus) + ", " +
                std::to_string(resolveStatus) + ")";
        return nullptr;
    }
    return t;
}

OffscreenTarget::~OffscreenTarget() {
    const GLuint fbos[] = {drawFbo_, resolveFbo_};
    glDeleteFramebuffers(2, fbos);
    const GLuint rbs[] = {colourRb_, depthRb_, resolveRb_};
    glDeleteRenderbuffers(3, rbs);
}

void OffscreenTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, drawFbo_);
    glDrawBuffer(GL_COLOR_ATTACHMENT0);
}

Image OffscreenTarget::read() const {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, drawFbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFbo_);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveFbo_);
    Image image(width_, height_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    flipRows(image);
    return image;
}

Image readWindow(int width, int height) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    Image image(width, height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    flipRows(image);
    return image;
}

}  // namespace hapticut::render
