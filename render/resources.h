#pragma once
// Move-only owners of GPU objects. A destructor never destroys its Vulkan handle: it hands it to
// the context's current retire list, which is freed once that frame's fence has signalled
// (Granite destroy_buffer_nolock), so a chunk can be unloaded while the GPU still reads it.
// Owners must not outlive their Context. Main thread only.

#include <cstdint>

#include "render/context.h"

namespace vx::render {

struct BufferCreateInfo {
    VkDeviceSize size = 0;
    VkBufferUsageFlags usage = 0; // Device addresses are always enabled.
    MemoryUse memory = MemoryUse::Device;
    VkDeviceSize alignment = 0;   // Extra minimum alignment (e.g. 256 for acceleration structures).
    const char* name = "buffer";
    // Scene memory (chunk geometry, BLASes): counts against the allocator's budget, and running
    // out is the caller's to report (create() then logs nothing).
    bool scene = false;
};

class Buffer {
public:
    Buffer() = default;
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    ~Buffer() { reset(); }

    // An empty Buffer (valid() false) and a log line when memory ran out.
    static Buffer create(Context& ctx, const BufferCreateInfo& info);

    bool valid() const { return m_buffer != VK_NULL_HANDLE; }
    VkBuffer handle() const { return m_buffer; }
    VkDeviceSize size() const { return m_size; }
    VkDeviceAddress address() const { return m_address; } // GPU virtual address of byte 0.
    void* mapped() const { return m_alloc.mapped; }       // Non-null for Upload/Readback memory.
    void reset(); // Retires the handle now.

private:
    Context* m_ctx = nullptr;
    VkBuffer m_buffer = VK_NULL_HANDLE;
    Allocation m_alloc;
    VkDeviceSize m_size = 0;
    VkDeviceAddress m_address = 0;
};

struct ImageCreateInfo {
    uint32_t width = 0, height = 0;
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    VkImageUsageFlags usage = 0;
    const char* name = "image";
    // Format of the view; UNDEFINED: `format`. Another (compatible) format makes the image
    // MUTABLE_FORMAT + EXTENDED_USAGE (e.g. an _SRGB image written as UNORM storage).
    VkFormat view_format = VK_FORMAT_UNDEFINED;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT; // DEPTH for a depth buffer.
};

// A 2D, single-mip image in device memory with one colour view.
class Image {
public:
    Image() = default;
    Image(Image&& o) noexcept { *this = std::move(o); }
    Image& operator=(Image&& o) noexcept;
    ~Image() { reset(); }

    static Image create(Context& ctx, const ImageCreateInfo& info);

    bool valid() const { return m_image != VK_NULL_HANDLE; }
    VkImage handle() const { return m_image; }
    VkImageView view() const { return m_view; }
    uint32_t width() const { return m_width; }
    uint32_t height() const { return m_height; }
    void reset();

private:
    Context* m_ctx = nullptr;
    VkImage m_image = VK_NULL_HANDLE;
    VkImageView m_view = VK_NULL_HANDLE;
    Allocation m_alloc;
    uint32_t m_width = 0, m_height = 0;
};

// An acceleration structure and the buffer holding it (at a 256-byte aligned offset).
class AccelStruct {
public:
    AccelStruct() = default;
    AccelStruct(AccelStruct&& o) noexcept { *this = std::move(o); }
    AccelStruct& operator=(AccelStruct&& o) noexcept;
    ~AccelStruct() { reset(); }

    // An empty AccelStruct when memory ran out. `scene`: as BufferCreateInfo::scene.
    static AccelStruct create(Context& ctx, VkAccelerationStructureTypeKHR type, VkDeviceSize size, const char* name,
                              bool scene = false);

    bool valid() const { return m_handle != VK_NULL_HANDLE; }
    VkAccelerationStructureKHR handle() const { return m_handle; }
    VkDeviceAddress address() const { return m_address; }
    VkDeviceSize size() const { return m_buffer.size(); }
    void reset();

private:
    Context* m_ctx = nullptr;
    VkAccelerationStructureKHR m_handle = VK_NULL_HANDLE;
    VkDeviceAddress m_address = 0;
    Buffer m_buffer;
};

} // namespace vx::render
