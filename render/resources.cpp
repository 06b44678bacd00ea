#include "render/resources.h"

#include <utility>

#include "world/base/log.h"

namespace vx::render {

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        reset();
        m_ctx = std::exchange(o.m_ctx, nullptr);
        m_buffer = std::exchange(o.m_buffer, VK_NULL_HANDLE);
        m_alloc = std::exchange(o.m_alloc, Allocation{});
        m_size = std::exchange(o.m_size, 0);
        m_address = std::exchange(o.m_address, 0);
    }
    return *this;
}

void Buffer::reset() {
    if (!m_buffer)
        return;
    RetireList& r = m_ctx->retire_list();
    r.buffers.push_back(m_buffer);
    r.allocations.push_back(m_alloc);
    m_buffer = VK_NULL_HANDLE;
    m_alloc = {};
    m_size = 0;
    m_address = 0;
}

Buffer Buffer::create(Context& ctx, const BufferCreateInfo& info) {
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = info.size;
    ci.usage = info.usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    Buffer b;
    // Past the device's largest buffer the create call is invalid usage, not an error result.
    const bool too_large = ctx.max_buffer_size() && info.size > ctx.max_buffer_size();
    if (too_large || VK_OUT_OF_MEMORY(vkCreateBuffer(ctx.device(), &ci, nullptr, &b.m_buffer))) {
        if (!info.scene)
            VX_LOG_ERROR("out of GPU memory for buffer '%s' (%llu bytes%s)", info.name, (unsigned long long)info.size,
                         too_large ? ": past the device's largest buffer" : "");
        return Buffer();
    }
    b.m_ctx = &ctx;
    b.m_size = info.size;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), b.m_buffer, &req);
    if (info.alignment > req.alignment)
        req.alignment = info.alignment;
    if (!ctx.allocation_injected(info.name, info.size)) // A test hook: as if the device were full.
        b.m_alloc = ctx.allocator().allocate(req, info.memory, false, info.scene);
    if (!b.m_alloc.valid()) {
        if (!info.scene)
            VX_LOG_ERROR("out of GPU memory for buffer '%s' (%llu bytes)", info.name, (unsigned long long)info.size);
        b.reset();
        return b;
    }
    if (VK_OUT_OF_MEMORY(vkBindBufferMemory(ctx.device(), b.m_buffer, b.m_alloc.memory, b.m_alloc.offset))) {
        if (!info.scene)
            VX_LOG_ERROR("out of GPU memory binding buffer '%s' (%llu bytes)", info.name, (unsigned long long)info.size);
        b.reset(); // The buffer and its allocation retire with this frame.
        return b;
    }
    VkBufferDeviceAddressInfo ai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    ai.buffer = b.m_buffer;
    b.m_address = vkGetBufferDeviceAddress(ctx.device(), &ai);
    ctx.set_name(b.m_buffer, VK_OBJECT_TYPE_BUFFER, info.name);
    return b;
}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        reset();
        m_ctx = std::exchange(o.m_ctx, nullptr);
        m_image = std::exchange(o.m_image, VK_NULL_HANDLE);
        m_view = std::exchange(o.m_view, VK_NULL_HANDLE);
        m_alloc = std::exchange(o.m_alloc, Allocation{});
        m_width = std::exchange(o.m_width, 0);
        m_height = std::exchange(o.m_height, 0);
    }
    return *this;
}

void Image::reset() {
    if (!m_image)
        return;
    RetireList& r = m_ctx->retire_list();
    if (m_view)
        r.views.push_back(m_view);
    r.images.push_back(m_image);
    r.allocations.push_back(m_alloc);
    m_image = VK_NULL_HANDLE;
    m_view = VK_NULL_HANDLE;
    m_alloc = {};
}

Image Image::create(Context& ctx, const ImageCreateInfo& info) {
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = info.format;
    ci.extent = {info.width, info.height, 1};
    ci.mipLevels = 1;
    ci.arrayLayers = 1;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = info.usage;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    const bool other_view = info.view_format != VK_FORMAT_UNDEFINED && info.view_format != info.format;
    if (other_view)
        ci.flags = VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT | VK_IMAGE_CREATE_EXTENDED_USAGE_BIT;
    Image img;
    if (VK_OUT_OF_MEMORY(vkCreateImage(ctx.device(), &ci, nullptr, &img.m_image))) {
        VX_LOG_ERROR("out of GPU memory for image '%s'", info.name);
        return Image();
    }
    img.m_ctx = &ctx;
    img.m_width = info.width;
    img.m_height = info.height;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), img.m_image, &req);
    if (!ctx.allocation_injected(info.name, req.size)) // A test hook: as if the device were full.
        img.m_alloc = ctx.allocator().allocate(req, MemoryUse::Device, true);
    if (!img.m_alloc.valid()) {
        VX_LOG_ERROR("out of GPU memory for image '%s'", info.name);
        img.reset();
        return img;
    }
    if (VK_OUT_OF_MEMORY(vkBindImageMemory(ctx.device(), img.m_image, img.m_alloc.memory, img.m_alloc.offset))) {
        VX_LOG_ERROR("out of GPU memory binding image '%s'", info.name);
        img.reset();
        return img;
    }
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = img.m_image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = other_view ? info.view_format : info.format;
    vi.subresourceRange = {info.aspect, 0, 1, 0, 1};
    if (VK_OUT_OF_MEMORY(vkCreateImageView(ctx.device(), &vi, nullptr, &img.m_view))) {
        VX_LOG_ERROR("out of memory for the view of image '%s'", info.name);
        img.m_view = VK_NULL_HANDLE;
        img.reset();
        return img;
    }
    ctx.set_name(img.m_image, VK_OBJECT_TYPE_IMAGE, info.name);
    ctx.set_name(img.m_view, VK_OBJECT_TYPE_IMAGE_VIEW, info.name);
    return img;
}

AccelStruct& AccelStruct::operator=(AccelStruct&& o) noexcept {
    if (this != &o) {
        reset();
        m_ctx = std::exchange(o.m_ctx, nullptr);
        m_handle = std::exchange(o.m_handle, VK_NULL_HANDLE);
        m_address = std::exchange(o.m_address, 0);
        m_buffer = std::move(o.m_buffer);
    }
    return *this;
}

void AccelStruct::reset() {
    if (m_handle)
        m_ctx->retire_list().accels.push_back(m_handle);
    m_handle = VK_NULL_HANDLE;
    m_address = 0;
    m_buffer.reset();
}

AccelStruct AccelStruct::create(Context& ctx, VkAccelerationStructureTypeKHR type, VkDeviceSize size,
                                const char* name, bool scene) {
    AccelStruct as;
    BufferCreateInfo bi;
    bi.size = size;
    bi.usage = VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR;
    bi.alignment = 256; // Acceleration structures must start at 256-byte offsets.
    bi.name = name;
    bi.scene = scene;
    as.m_buffer = Buffer::create(ctx, bi);
    if (!as.m_buffer.valid())
        return as;
    as.m_ctx = &ctx;
    VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
    ci.buffer = as.m_buffer.handle();
    ci.offset = 0;
    ci.size = size;
    ci.type = type;
    if (VK_OUT_OF_MEMORY(vkCreateAccelerationStructureKHR(ctx.device(), &ci, nullptr, &as.m_handle))) {
        if (!scene)
            VX_LOG_ERROR("out of memory for acceleration structure '%s'", name);
        as.m_handle = VK_NULL_HANDLE;
        as.m_buffer.reset();
        return as;
    }
    VkAccelerationStructureDeviceAddressInfoKHR ai{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
    ai.accelerationStructure = as.m_handle;
    as.m_address = vkGetAccelerationStructureDeviceAddressKHR(ctx.device(), &ai);
    ctx.set_name(as.m_handle, VK_OBJECT_TYPE_ACCELERATION_STRUCTURE_KHR, name);
    return as;
}

} // namespace vx::render
