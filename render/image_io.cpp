#include <stb/stb_image_write.h>

#include "render/renderer.h"

namespace vx::render {

Status write_png(const std::string& path, const RenderImage& image) {
    if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
        return Error{"write_png: empty or malformed image"};
    if (!stbi_write_png(path.c_str(), int(image.width), int(image.height), 4, image.rgba.data(), int(image.width * 4)))
        return Error{"cannot write PNG " + path};
    return {};
}

} // namespace vx::render
