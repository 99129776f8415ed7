// RGBA8 images in memory, written to and read from PNG files; statistics the screenshot tests use.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hapticut::render {

struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // row 0 is the top row

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4, 0) {}
    std::uint8_t* at(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
    const std::uint8_t* at(int x, int y) const { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

/// Writes a PNG through a temporary file and a rename; the error message names the file when it fails.
std::optional<std::string> savePng(const std::filesystem::path& file, const Image& image);

/// Reads a PNG (any channel count, returned as RGBA); the error message names the file and the reason.
std::optional<Image> loadPng(const std::filesystem::path& file, std::string& error);

/// Flips rows in place: OpenGL reads the bottom row first.
void flipRows(Image& image);

}  // namespace hapticut::render
