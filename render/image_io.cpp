#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include <stb/stb_image_write.h>

#include "render/renderer.h"

namespace vx::render {
namespace {

// stb's file writer ignores fwrite's and fclose's errors: a full disk left a cut PNG and
// reported success. So the PNG is encoded into memory and written here, every call checked.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* bytes = static_cast<const unsigned char*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

Status write_all(const std::string& path, const std::vector<unsigned char>& bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f)
        return Error{"cannot write PNG " + path + ": " + std::strerror(errno)};
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
    const int err = errno;
    const bool closed = std::fclose(f) == 0;
    if (written && closed)
        return {};
    std::error_code ec; // A cut PNG is worse than none; a device (/dev/full) stays.
    if (std::filesystem::is_regular_file(path, ec))
        std::filesystem::remove(path, ec);
    return Error{"cannot write PNG " + path + ": " + std::strerror(written ? errno : err)};
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
