#pragma once
// What the Vulkan devices of this machine can do, without creating a logical device: for `vx info`
// and for choosing the device to render with. No Vulkan types in this header.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "world/base/result.h"

namespace vx::render {

enum class DeviceType : uint8_t { Other, Integrated, Discrete, Virtual, Cpu };
const char* device_type_name(DeviceType type);

struct DeviceReport {
    uint32_t index = 0;           // Position in vkEnumeratePhysicalDevices order.
    std::string name;
    DeviceType type = DeviceType::Other;
    uint32_t api_version = 0;     // VK_MAKE_API_VERSION encoding, as the driver reports it.
    std::string driver_info;      // Driver name and info strings (e.g. "llvmpipe / Mesa 25.0.7").
    bool acceleration_structure = false;   // VK_KHR_acceleration_structure + feature.
    bool ray_tracing_pipeline = false;     // VK_KHR_ray_tracing_pipeline + feature.
    bool deferred_host_operations = false; // VK_KHR_deferred_host_operations.
    bool buffer_device_address = false;    // Vulkan 1.2 bufferDeviceAddress feature.
    // VK_EXT_shader_atomic_float's shaderBufferFloat32AtomicAdd: the light cache's sums
    // (shaders/shared/light_cache.glsl), compiled into the ray generation shader.
    bool float_atomic_add = false;
    // Compute shaders have subgroup ballot and arithmetic operations (Vulkan 1.1 subgroup
    // properties): the light cache's gather pass (shaders/light_cache_gather.comp) sums a
    // subgroup's hits of one cell before its atomics.
    bool compute_subgroup_sums = false;
    // Vulkan 1.3 maxBufferSize (bytes; 0 below 1.3): a larger buffer cannot be made at all.
    uint64_t max_buffer_size = 0;
    uint64_t device_memory = 0; // The largest device-local memory heap, bytes.
    // Only filled in by a Context created with a window: VK_KHR_swapchain exists and a queue
    // family with graphics + compute can present to the window's surface.
    bool present = false;

    // Everything the renderer needs (it also needs Vulkan 1.3: see api_version).
    bool can_ray_trace() const;
    std::string api_version_string() const; // "1.4.303"
};

// Enumerates the devices through a temporary instance. Returns an error (never crashes) when no
// Vulkan loader or driver is installed. Slow (creates an instance): call rarely. Main thread
// only (volk's function pointers are process globals); safe while a Context exists.
Result<std::vector<DeviceReport>> probe_devices();

// Thread-safe. The one line for "the Vulkan loader found no driver" (vkCreateInstance returned
// VK_ERROR_INCOMPATIBLE_DRIVER, or no device): which driver files it looked for. `driver_files`
// and `icd_filenames` are the values of VK_DRIVER_FILES and VK_ICD_FILENAMES (null: unset; the
// loader takes the first set, else searches the default icd.d directories); listed files that
// do not exist are named.
std::string missing_driver_message(const char* driver_files, const char* icd_filenames);

// Which device to use: "auto" prefers a ray-tracing discrete GPU, then any ray-tracing device;
// "cpu" wants a CPU device (lavapipe); "gpu" any non-CPU device; "N" the device at index N.
struct DeviceChoice {
    enum class Kind : uint8_t { Auto, Cpu, Gpu, Index } kind = Kind::Auto;
    uint32_t index = 0; // For Kind::Index.
};
Result<DeviceChoice> parse_device_choice(std::string_view text);

// The index into `devices` to use, or an error saying why none fits. need_present: only devices
// whose `present` is set qualify (rendering to a window). Thread-safe.
Result<uint32_t> choose_device(const std::vector<DeviceReport>& devices, DeviceChoice choice, bool need_present = false);

} // namespace vx::render
