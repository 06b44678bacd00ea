// Context frames, retire lists and one-shot submissions.
#include "render/context.h"

#include <string>

#include "world/base/assert.h"
#include "world/base/log.h"

namespace vx::render {

VkResult Context::make_pool(VkCommandPool& pool, const char* name) {
    VkCommandPoolCreateInfo ci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    ci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    ci.queueFamilyIndex = m_queue_family;
    const VkResult r =
        create_call("vkCreateCommandPool", name, [&] { return vkCreateCommandPool(m_device, &ci, nullptr, &pool); });
    if (r == VK_SUCCESS)
        set_name(pool, VK_OBJECT_TYPE_COMMAND_POOL, name);
    return r;
}

VkResult Context::make_cmd(VkCommandPool pool, VkCommandBuffer& cmd, const char* name) {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    const VkResult r =
        create_call("vkAllocateCommandBuffers", name, [&] { return vkAllocateCommandBuffers(m_device, &ai, &cmd); });
    if (r == VK_SUCCESS)
        set_name(cmd, VK_OBJECT_TYPE_COMMAND_BUFFER, name);
    return r;
}

VkResult Context::make_fence(VkFence& fence, bool signalled, const char* name) {
    VkFenceCreateInfo ci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    ci.flags = signalled ? VK_FENCE_CREATE_SIGNALED_BIT : 0;
    const VkResult r =
        create_call("vkCreateFence", name, [&] { return vkCreateFence(m_device, &ci, nullptr, &fence); });
    if (r == VK_SUCCESS)
        set_name(fence, VK_OBJECT_TYPE_FENCE, name);
    return r;
}

// Out of memory here was a VK_CHECK abort: an error naming the call; ~Context frees what was made.
Status Context::create_frames() {
    VkResult r = VK_SUCCESS;
    for (uint32_t i = 0; i < kFramesInFlight && r == VK_SUCCESS; ++i) {
        Frame& f = m_frames[i];
        r = make_pool(f.pool, i ? "frame pool 1" : "frame pool 0");
        if (r == VK_SUCCESS)
            r = make_cmd(f.pool, f.cmd, i ? "frame cmd 1" : "frame cmd 0");
        if (r == VK_SUCCESS)
            r = make_fence(f.fence, true, i ? "frame fence 1" : "frame fence 0");
    }
    if (r == VK_SUCCESS)
        r = make_pool(m_one_shot_pool, "one-shot pool");
    if (r == VK_SUCCESS)
        r = make_fence(m_one_shot_fence, false, "one-shot fence");
    if (r != VK_SUCCESS)
        return Error{"cannot create the Vulkan context's frames: " + m_last_create_failure};
    return {};
}

void Context::flush(RetireList& list) {
    // Acceleration structures and views before the buffers and images under them.
    for (VkAccelerationStructureKHR a : list.accels)
        vkDestroyAccelerationStructureKHR(m_device, a, nullptr);
    for (VkImageView v : list.views)
        vkDestroyImageView(m_device, v, nullptr);
    for (VkImage i : list.images)
        vkDestroyImage(m_device, i, nullptr);
    for (VkBuffer b : list.buffers)
        vkDestroyBuffer(m_device, b, nullptr);
    for (VkPipeline p : list.pipelines)
        vkDestroyPipeline(m_device, p, nullptr);
    for (const Allocation& a : list.allocations)
        m_allocator->free(a);
    list = RetireList{};
}

void Context::log_create_failure(const char* what, VkResult result) {
    m_last_create_failure = std::string(what) + " failed (" + vk_result_name(result) + ")";
    VX_LOG_ERROR("renderer: %s", m_last_create_failure.c_str());
}

bool Context::check_device(VkResult result, const char* what) {
    if (const VkResult injected = m_faults.take_call(what); injected != VK_SUCCESS) // Test hook.
        result = injected;
    if (result == VK_SUCCESS)
        return true;
    // Out of memory in a submit or a wait leaves the frame's fence unsignalled for good (the
    // spec: as if not submitted); a lost surface, an unknown error: nothing after it can be
    // trusted either. The device is given up as lost, and the renderer recreated, never aborted.
    if (!m_lost && result == VK_ERROR_DEVICE_LOST)
        VX_LOG_ERROR("renderer: the GPU device was lost (%s); frames fail until the renderer is recreated", what);
    else if (!m_lost)
        VX_LOG_ERROR("renderer: %s failed (%s): the device is treated as lost; frames fail until the renderer is "
                     "recreated", what, vk_result_name(result));
    m_lost = true;
    return false;
}

VkCommandBuffer Context::begin_frame() {
    VX_ASSERT(!m_in_frame);
    if (m_lost)
        return VK_NULL_HANDLE;
    const uint32_t slot = uint32_t((m_frame_number + 1) % kFramesInFlight);
    Frame& f = m_frames[slot];
    // The slot's fence covers its last submission; with kFramesInFlight >= 2 every earlier frame
    // was waited for when its own slot began again, so everything retired in this slot is idle.
    if (!check_device(wait_fence(f.fence), "vkWaitForFences"))
        return VK_NULL_HANDLE;
    m_frame_slot = slot;
    ++m_frame_number;
    flush(f.retire);
    // Out of memory resetting or beginning the frame's commands: a lost context, as for a submit
    // (they aborted). The fence is reset only after them, so it stays signalled on that path.
    if (!check_device(vkResetCommandPool(m_device, f.pool, 0), "vkResetCommandPool"))
        return VK_NULL_HANDLE;
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (!check_device(vkBeginCommandBuffer(f.cmd, &bi), "vkBeginCommandBuffer"))
        return VK_NULL_HANDLE;
    if (!check_device(vkResetFences(m_device, 1, &f.fence), "vkResetFences"))
        return VK_NULL_HANDLE; // Its buffer is recording, never submitted: the context is lost.
    m_in_frame = true;
    return f.cmd;
}

// The injected loss (simulate_device_loss) replaces the submission, so nothing runs after it;
// nothing is submitted to a lost device either.
VkResult Context::submit(const VkSubmitInfo2& si, VkFence fence) {
    if (m_lost)
        return VK_ERROR_DEVICE_LOST;
    if (m_simulate_loss) {
        m_simulate_loss = false;
        return VK_ERROR_DEVICE_LOST;
    }
    return vkQueueSubmit2(m_queue, 1, &si, fence);
}

// The injected hang (simulate_hang) skips the wait: what it waited for stays pending.
VkResult Context::wait_fence(VkFence fence) {
    if (m_simulate_hang) {
        m_simulate_hang = false;
        return VK_ERROR_DEVICE_LOST;
    }
    return vkWaitForFences(m_device, 1, &fence, VK_TRUE, UINT64_MAX);
}

bool Context::end_frame(const FrameSubmitSync& sync) {
    VX_ASSERT(m_in_frame);
    m_in_frame = false;
    Frame& f = m_frames[m_frame_slot];
    if (!check_device(vkEndCommandBuffer(f.cmd), "vkEndCommandBuffer"))
        return false; // Out of memory recording the frame: nothing is submitted.
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = f.cmd;
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = sync.wait;
    wait.stageMask = sync.wait_stage;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = sync.signal;
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    si.waitSemaphoreInfoCount = sync.wait ? 1 : 0;
    si.pWaitSemaphoreInfos = &wait;
    si.signalSemaphoreInfoCount = sync.signal ? 1 : 0;
    si.pSignalSemaphoreInfos = &signal;
    return check_device(submit(si, f.fence), "vkQueueSubmit2");
}

bool Context::wait_frame() {
    VX_ASSERT(!m_in_frame);
    if (m_lost)
        return false;
    return check_device(wait_fence(m_frames[m_frame_slot].fence), "vkWaitForFences");
}

void Context::wait_idle() {
    VX_ASSERT(!m_in_frame);
    // A lost device still lets its objects be destroyed; only the wait's result is moot then.
    check_device(vkDeviceWaitIdle(m_device), "vkDeviceWaitIdle");
    for (Frame& f : m_frames)
        flush(f.retire);
}

// Out of memory resetting, allocating or beginning the one-shot buffer marks the context lost
// (it was a VK_CHECK abort): null, and submit_now records nothing.
VkCommandBuffer Context::begin_one_shot() {
    if (m_lost)
        return VK_NULL_HANDLE; // Nothing would be submitted.
    // A stranded buffer may be pending: the pool must not be reset.
    if (!m_one_shot_stranded &&
        !check_device(vkResetCommandPool(m_device, m_one_shot_pool, 0), "vkResetCommandPool (one-shot)"))
        return VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (!check_device(make_cmd(m_one_shot_pool, cmd, "one-shot cmd"), "vkAllocateCommandBuffers (one-shot cmd)"))
        return VK_NULL_HANDLE;
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (!check_device(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer (one-shot)")) {
        vkFreeCommandBuffers(m_device, m_one_shot_pool, 1, &cmd);
        return VK_NULL_HANDLE;
    }
    return cmd;
}

void Context::end_one_shot(VkCommandBuffer cmd) {
    if (!check_device(vkEndCommandBuffer(cmd), "vkEndCommandBuffer (one-shot)")) {
        vkFreeCommandBuffers(m_device, m_one_shot_pool, 1, &cmd); // Never submitted.
        return;
    }
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = cmd;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    if (!check_device(submit(si, m_one_shot_fence), "vkQueueSubmit2")) {
        vkFreeCommandBuffers(m_device, m_one_shot_pool, 1, &cmd); // Never submitted.
        return;
    }
    if (!check_device(wait_fence(m_one_shot_fence), "vkWaitForFences")) {
        // Lost while it may still be pending: freeing it is invalid. It stays allocated and goes
        // with its pool, destroyed after the destructor's vkDeviceWaitIdle; a lost context
        // submits nothing again, so neither it nor the fence is reused.
        m_one_shot_stranded = true;
        return;
    }
    // Out of device memory resetting the fence: lost (a signalled fence must not be reused).
    check_device(vkResetFences(m_device, 1, &m_one_shot_fence), "vkResetFences (one-shot)");
    vkFreeCommandBuffers(m_device, m_one_shot_pool, 1, &cmd);
}

} // namespace vx::render
