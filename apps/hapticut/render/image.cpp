// PNG files through stb (Debian's libstb), written atomically.
#include "render/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>

#include "hapticut/common/text_file.h"

namespace hapticut::render {

std::optional<std::string> savePng(const std::filesystem::path& file, const Image& image) {
    if (image.width <= 0 || image.height <= 0) return file.string() + ": nothing to write, the image is empty";
    std::string bytes;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 4, image.rgba.data(), image.width * 4))
        return file.string() + ": could not encode the PNG";
    if (const auto error = writeTextFileAtomically(file, bytes)) return error->toString();
    return std::nullopt;
}

std::optional<Image> loadPng(const std::filesystem::path& file, std::string& error) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(file.string().c_str(), &w, &h, &channels, 4);
    if (!data) {
        error = file.string() +
                ": cannot read the image: " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown reason");
        return std::nullopt;
    }
    Image image(w, h);
    std::copy(data, data + image.rgba.size(), image.rgba.begin());
    stbi_image_free(data);
    return image;
}

void flipRows(Image& image) {
    const std::size_t row = static_cast<std::size_t>(image.width) * 4;
    for (int y = 0; y < image.height / 2; ++y)
        std::swap_ranges(image.rgba.begin() + static_cast<std::ptrdiff_t>(y * row),
                         image.rgba.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                         image.rgba.begin() + static_cast<std::ptrdiff_t>((image.height - 1 - y) * row));
}

}  // namespace hapticut::render
