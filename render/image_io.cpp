#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include <stb/stb_image_write.h>

#include "render/renderer.h"
#include "world/base/file_replace.h"

namespace vx::render {
namespace {

// stb's file writer ignores fwrite's and fclose's errors: a full disk left a cut PNG and
// reported success. So the PNG is encoded into memory and written here, every call checked.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* bytes = static_cast<const unsigned char*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

// Written whole or not at all (world/base/file_replace.h): a temporary beside the path is renamed
// over it once every byte is written and closed, so a full disk leaves the previous image, not a
// cut one that a viewer would show as whole.
Status write_all(const std::string& path, const std::vector<unsigned char>& bytes) {
    world::ReplacingFile file;
    Status s = file.open(path, "wb");
    if (s && std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size())
        s = Error{"write to '" + path + "' failed: " + std::strerror(errno)};
    if (s)
        s = file.commit(); // The flush and the close are checked there.
    if (!s)
        return Error{"cannot write PNG: " + s.error()};
    return {};
}

} // namespace

Status write_png(const std::string& path, const RenderImage& image) {
    if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
        return Error{"write_png: empty or malformed image"};
    std::vector<unsigned char> png;
    if (!stbi_write_png_to_func(append_bytes, &png, int(image.width), int(image.height), 4, image.rgba.data(),
                                int(image.width * 4)))
        return Error{"cannot encode PNG " + path};
    return write_all(path, png);
}

} // namespace vx::render
