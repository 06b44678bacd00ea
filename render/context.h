#pragma once
// The Vulkan context: instance (API 1.3, optional validation + a debug messenger that counts
// errors), the chosen physical device, a logical device with the ray-tracing features and one
// queue, the memory allocator, and the frame ring whose retire lists free GPU objects once the
// frame that last used them has finished (Granite's PerFrame). With a window it also owns the
// window's surface (the swapchain lives in swapchain.h); without one it is headless.
// One Context per process at a time: volk keeps Vulkan entry points in process globals.
// Main thread only.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "render/device_probe.h"
#include "render/fault_injection.h"
#include "render/gpu_allocator.h"
#include "render/vk_common.h"

namespace vx::render {

struct ContextCreateInfo {
    bool validation = false;   // Enable VK_LAYER_KHRONOS_validation if it is installed.
    bool sync_validation = false; // With validation: also its synchronization checks (slow).
    DeviceChoice device{};     // Which device to use.
    const char* app_name = "vx";
    // Test hook: Context::fail_allocations from the start, so the frames' pools, buffers and
    // fences can be refused too (create returns an error). Empty: none.
    std::string fail_allocations{};
    // A GLFWwindow* to present to, or null (headless). With a window the instance enables GLFW's
    // surface extensions, the device must present from its graphics+compute queue, and
    // VK_KHR_swapchain is enabled. The caller keeps GLFW initialised and the window alive
    // until the Context is destroyed.
    void* window = nullptr;
    // Ask the driver to keep statistics of the pipelines it compiles (register counts, code size:
    // VK_KHR_pipeline_executable_properties), where the device offers them; see
    // Context::pipeline_statistics(). Off by default: drivers may compile differently or skip their
    // caches with it on.
    bool pipeline_statistics = false;
};

// Semaphores of a frame's submission (presentation): wait on `wait` at `wait_stage` (the
// acquired swapchain image), signal `signal` when the frame's commands have finished.
struct FrameSubmitSync {
    VkSemaphore wait = VK_NULL_HANDLE;
    VkPipelineStageFlags2 wait_stage = VK_PIPELINE_STAGE_2_NONE;
    VkSemaphore signal = VK_NULL_HANDLE;
};

inline constexpr uint32_t kFramesInFlight = 2;

// Handles a destroyed owner hands over; freed when their frame's fence has signalled.
struct RetireList {
    std::vector<VkAccelerationStructureKHR> accels;
    std::vector<VkImageView> views;
    std::vector<VkImage> images;
    std::vector<VkBuffer> buffers;
    std::vector<Allocation> allocations;
    std::vector<VkPipeline> pipelines;
};

class Context {
public:
    // Creates everything; an error (not a crash) when no loader or no ray-tracing device exists.
    static Result<std::unique_ptr<Context>> create(const ContextCreateInfo& info);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return m_instance; }
    VkPhysicalDevice physical_device() const { return m_pd; }
    VkDevice device() const { return m_device; }
    VkQueue queue() const { return m_queue; }
    uint32_t queue_family() const { return m_queue_family; }
    VkSurfaceKHR surface() const { return m_surface; } // VK_NULL_HANDLE when headless.
    void* window() const { return m_window; }          // The GLFWwindow*, or null.
    const DeviceReport& report() const { return m_report; }
    const VkPhysicalDeviceRayTracingPipelinePropertiesKHR& rt_properties() const { return m_rt_props; }
    const VkPhysicalDeviceAccelerationStructurePropertiesKHR& as_properties() const { return m_as_props; }
    const VkPhysicalDeviceLimits& limits() const { return m_limits; }
    // The largest buffer the device may create (Vulkan 1.3 maxBufferSize), bytes.
    VkDeviceSize max_buffer_size() const { return m_max_buffer_size; }
    GpuAllocator& allocator() { return *m_allocator; }

    // Validation-layer messages of severity error seen so far (tests assert 0). Thread-safe.
    uint32_t validation_errors() const { return m_validation_errors.load(); }
    uint32_t validation_warnings() const { return m_validation_warnings.load(); }
    bool validation_enabled() const { return m_validation; }
    bool sync_validation_enabled() const { return m_sync_validation; }
    // Pipelines are made with VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR and their statistics
    // can be read (render/pipeline_report.h); else pipeline_statistics_note() says why not.
    bool pipeline_statistics() const { return m_pipeline_statistics; }
    const std::string& pipeline_statistics_note() const { return m_statistics_note; }

    // Names an object for validation messages and debuggers (no-op without debug utils).
    void set_name(VkObjectType type, uint64_t handle, const char* name) const;
    template <class T> void set_name(T handle, VkObjectType type, const char* name) const {
        set_name(type, uint64_t(handle), name);
    }

    // Frames: begin_frame waits until this slot's previous submission finished, frees its retire
    // list and returns a command buffer in the recording state; end_frame submits it (with the
    // semaphores of `sync` when presenting). The only CPU wait on the GPU per frame is the one in
    // begin_frame: on the frame kFramesInFlight back.
    // A lost device (VK_ERROR_DEVICE_LOST from a submit or a wait: a result a correct program
    // can meet) is not a crash: the context marks itself lost() and logs once; begin_frame then
    // returns VK_NULL_HANDLE, end_frame and wait_frame false, and nothing is submitted again.
    VkCommandBuffer begin_frame();
    bool end_frame(const FrameSubmitSync& sync = {});
    // Waits for every submitted frame and frees every retire list (also on a lost device).
    void wait_idle();
    uint64_t frame_number() const { return m_frame_number; }
    // Slot (0..kFramesInFlight-1) of the frame being recorded or last submitted.
    uint32_t frame_slot() const { return m_frame_slot; }
    // Waits until the last submitted frame has completed (for read-back); false: device lost.
    bool wait_frame();
    // The device was lost: the renderer must be recreated (its objects may only be destroyed).
    bool lost() const { return m_lost; }
    // `result` of a submit, wait, acquire, present, command-buffer end or query read: any failure
    // (VK_ERROR_DEVICE_LOST, out of memory, a lost surface) marks the context lost and returns
    // false, logged once. `what` names the call for the log line (and for inject_result).
    bool check_device(VkResult result, const char* what);

    // Test hooks (tests and fault-injection only). simulate_device_loss: the next submission is
    // not made and reads as VK_ERROR_DEVICE_LOST, as when the GPU hangs or its driver resets.
    // fail_allocations: Buffer::create and Image::create of resources whose debug name starts
    // with `name_prefix` fail as out of memory (logged) until called again with "" (none); with
    // `above_bytes` > 0 only those larger than that fail (a device with room for smaller ones).
    void simulate_device_loss() { m_simulate_loss = true; }
    // simulate_hang: the next fence wait is not made and reads as VK_ERROR_DEVICE_LOST, its
    // submission left pending, as when the GPU hangs and the driver gives the device up.
    void simulate_hang() { m_simulate_hang = true; }
    // inject_result: the next check_device, create_call or new block's vkMapMemory for `call`
    // (its `what`) sees `result`.
    void inject_result(std::string call, VkResult result) {
        m_faults.call = std::move(call);
        m_faults.result = result;
    }
    // Also fails create_call and new memory blocks' vkMapMemory ("vkMapMemory") whose `what`
    // starts with `name_prefix`, as VK_ERROR_OUT_OF_HOST_MEMORY.
    void fail_allocations(std::string name_prefix, VkDeviceSize above_bytes = 0) {
        m_faults.prefix = std::move(name_prefix);
        m_faults.above = above_bytes;
    }
    // `bytes`: the allocation's size (0: one without a size, such as a pipeline).
    bool allocation_injected(const char* name, VkDeviceSize bytes = 0) const {
        return m_faults.allocation(name, bytes);
    }
    // A creation call the device may refuse at run time (out of host or device memory): returns
    // `call()`'s result, or without calling it the result a test hook gave `what` (inject_result,
    // fail_allocations). A failure is logged and kept (last_create_failure) naming `what`; the
    // caller turns it into an error (a Status, an empty resource), never an abort.
    template <class F> VkResult create_call(const char* what, F&& call) {
        VkResult r = m_faults.take(what);
        if (r == VK_SUCCESS)
            r = call();
        if (r != VK_SUCCESS)
            log_create_failure(what, r);
        return r;
    }

    // create_call for the object named `object`: `what` is "<call> (<object>)".
    template <class F> VkResult create_call(const char* call, const char* object, F&& make) {
        const std::string what = std::string(call) + " (" + object + ")";
        return create_call(what.c_str(), std::forward<F>(make));
    }

    // "<what> failed (<result>)" of the last create_call that failed, for error messages that
    // name the call; empty: none failed.
    const std::string& last_create_failure() const { return m_last_create_failure; }

    // Retiring: called by resource destructors; the handle is destroyed once the current frame
    // (and so every earlier one) has completed on the GPU.
    RetireList& retire_list() { return m_frames[m_frame_slot].retire; }

    // Records `record` into a fresh command buffer, submits it and waits (uploads, tests).
    // On a lost device (also one lost making the buffer: out of memory) `record` is not called
    // and nothing runs (callers see lost()).
    template <class F> void submit_now(F&& record) {
        VkCommandBuffer cmd = begin_one_shot();
        if (!cmd)
            return; // Lost (logged).
        record(cmd);
        end_one_shot(cmd);
    }

private:
    Context() = default;
    Status create_instance(const ContextCreateInfo& info);
    Status create_surface(const ContextCreateInfo& info);
    Status pick_device(const ContextCreateInfo& info);
    bool can_present(VkPhysicalDevice pd, uint32_t* family);
    void log_create_failure(const char* what, VkResult result);
    Status create_device(bool pipeline_statistics);
    Status create_frames();
    VkResult make_pool(VkCommandPool& pool, const char* name);
    VkResult make_cmd(VkCommandPool pool, VkCommandBuffer& cmd, const char* name);
    VkResult make_fence(VkFence& fence, bool signalled, const char* name);
    void flush(RetireList& list);
    VkCommandBuffer begin_one_shot();
    void end_one_shot(VkCommandBuffer cmd);
    VkResult submit(const VkSubmitInfo2& si, VkFence fence);
    VkResult wait_fence(VkFence fence); // vkWaitForFences without a timeout (or simulate_hang).
    static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT types,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                         void* user);

    struct Frame {
        VkCommandPool pool = VK_NULL_HANDLE;
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        RetireList retire;
    };

    VkInstance m_instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
    VkSurfaceKHR m_surface = VK_NULL_HANDLE;
    void* m_window = nullptr;
    VkPhysicalDevice m_pd = VK_NULL_HANDLE;
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queue_family = 0;
    bool m_validation = false;
    bool m_sync_validation = false; // Its synchronization checks too (ContextCreateInfo).
    bool m_debug_utils = false;
    bool m_pipeline_statistics = false;
    std::string m_statistics_note = "not asked for (ContextCreateInfo::pipeline_statistics)";
    DeviceReport m_report;
    VkPhysicalDeviceRayTracingPipelinePropertiesKHR m_rt_props{};
    VkPhysicalDeviceAccelerationStructurePropertiesKHR m_as_props{};
    VkDeviceSize m_max_buffer_size = 0;
    VkPhysicalDeviceLimits m_limits{};
    std::unique_ptr<GpuAllocator> m_allocator;
    std::array<Frame, kFramesInFlight> m_frames{};
    uint32_t m_frame_slot = 0;
    uint64_t m_frame_number = 0;
    bool m_in_frame = false;
    bool m_lost = false;
    bool m_simulate_loss = false;
    bool m_simulate_hang = false;
    FaultInjection m_faults; // inject_result, fail_allocations; the allocator reads it too.
    std::string m_last_create_failure;
    VkCommandPool m_one_shot_pool = VK_NULL_HANDLE;
    VkFence m_one_shot_fence = VK_NULL_HANDLE;
    bool m_one_shot_stranded = false; // A one-shot's wait failed: it is left in its pool.
    std::atomic<uint32_t> m_validation_errors{0};
    std::atomic<uint32_t> m_validation_warnings{0};
};

} // namespace vx::render
