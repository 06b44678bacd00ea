#include "render/device_probe.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "render/device_probe_internal.h"
#include "render/vk_common.h"

namespace vx::render {

const char* device_type_name(DeviceType type) {
    switch (type) {
    case DeviceType::Integrated: return "integrated GPU";
    case DeviceType::Discrete: return "discrete GPU";
    case DeviceType::Virtual: return "virtual GPU";
    case DeviceType::Cpu: return "CPU";
    default: return "other";
    }
}

bool DeviceReport::can_ray_trace() const {
    return acceleration_structure && ray_tracing_pipeline && deferred_host_operations &&
           buffer_device_address && float_atomic_add && compute_subgroup_sums &&
           api_version >= VK_API_VERSION_1_3;
}

std::string DeviceReport::api_version_string() const {
    return std::to_string(VK_API_VERSION_MAJOR(api_version)) + "." +
           std::to_string(VK_API_VERSION_MINOR(api_version)) + "." + std::to_string(VK_API_VERSION_PATCH(api_version));
}

static DeviceType to_device_type(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return DeviceType::Integrated;
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return DeviceType::Discrete;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return DeviceType::Virtual;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return DeviceType::Cpu;
    default: return DeviceType::Other;
    }
}

static bool has_extension(const std::vector<VkExtensionProperties>& exts, const char* name) {
    for (const VkExtensionProperties& e : exts)
        if (std::strcmp(e.extensionName, name) == 0)
            return true;
    return false;
}

static std::vector<VkExtensionProperties> device_extensions(VkPhysicalDevice pd) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
    return exts;
}

bool device_has_extension(VkPhysicalDevice pd, const char* name) {
    return has_extension(device_extensions(pd), name);
}

DeviceReport describe_device(VkPhysicalDevice pd, uint32_t index) {
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES, &subgroup};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
    vkGetPhysicalDeviceProperties2(pd, &props);

    const std::vector<VkExtensionProperties> exts = device_extensions(pd);

    DeviceReport r;
    r.index = index;
    r.name = props.properties.deviceName;
    r.type = to_device_type(props.properties.deviceType);
    r.api_version = props.properties.apiVersion;
    r.driver_info = std::string(driver.driverName) + " / " + driver.driverInfo;
    const VkSubgroupFeatureFlags sums = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT |
                                        VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    r.compute_subgroup_sums = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                              (subgroup.supportedOperations & sums) == sums;
    if (r.api_version >= VK_API_VERSION_1_3) { // Chaining a 1.3 struct below 1.3 is invalid.
        VkPhysicalDeviceVulkan13Properties p13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES};
        VkPhysicalDeviceProperties2 with13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p13};
        vkGetPhysicalDeviceProperties2(pd, &with13);
        r.max_buffer_size = p13.maxBufferSize;
    }
    VkPhysicalDeviceMemoryProperties mem{};
    vkGetPhysicalDeviceMemoryProperties(pd, &mem);
    for (uint32_t h = 0; h < mem.memoryHeapCount; ++h)
        if (mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            r.device_memory = std::max<uint64_t>(r.device_memory, mem.memoryHeaps[h].size);

    // Features are only queried for extensions that exist (chaining unknown structs is invalid).
    VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
    const bool has_atomics = has_extension(exts, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    if (has_atomics) {
        atomics.pNext = f2.pNext;
        f2.pNext = &atomics;
    }
    const bool has_as = has_extension(exts, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME);
    const bool has_rt = has_extension(exts, VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
    if (has_as) {
        as.pNext = f2.pNext;
        f2.pNext = &as;
    }
    if (has_rt) {
        rt.pNext = f2.pNext;
        f2.pNext = &rt;
    }
    if (r.api_version >= VK_API_VERSION_1_2)
        vkGetPhysicalDeviceFeatures2(pd, &f2);
    r.acceleration_structure = has_as && as.accelerationStructure;
    r.ray_tracing_pipeline = has_rt && rt.rayTracingPipeline;
    r.deferred_host_operations = has_extension(exts, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
    r.buffer_device_address = v12.bufferDeviceAddress;
    r.float_atomic_add = has_atomics && atomics.shaderBufferFloat32AtomicAdd;
    return r;
}

std::string missing_driver_message(const char* driver_files, const char* icd_filenames) {
    const char* variable = driver_files ? "VK_DRIVER_FILES" : icd_filenames ? "VK_ICD_FILENAMES" : nullptr;
    const char* value = driver_files ? driver_files : icd_filenames;
    if (!variable)
        return "no Vulkan driver found: none in the default driver directories (/etc/xdg/vulkan/icd.d, "
               "/etc/vulkan/icd.d, /usr/local/share/vulkan/icd.d, /usr/share/vulkan/icd.d, "
               "~/.local/share/vulkan/icd.d); install one (Debian: mesa-vulkan-drivers has lavapipe, a CPU "
               "driver) or set VK_DRIVER_FILES to its .json file";
    std::string missing;
    std::string_view rest = value;
    while (!rest.empty()) { // A ':'-separated list of .json files (or folders of them).
        const size_t colon = rest.find(':');
        const std::string file(rest.substr(0, colon));
        rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
        std::error_code ec;
        if (!file.empty() && !std::filesystem::exists(file, ec))
            missing += (missing.empty() ? "" : ", ") + file;
    }
    std::string out = std::string("no Vulkan driver found: looked only at ") + variable + "=" + value;
    out += missing.empty() ? " (the files exist but hold no usable driver)" : " (missing: " + missing + ")";
    return out + "; fix or unset " + variable + " to search the default icd.d directories";
}

std::string instance_error(VkResult r) {
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        return missing_driver_message(std::getenv("VK_DRIVER_FILES"), std::getenv("VK_ICD_FILENAMES"));
    return std::string("vkCreateInstance failed: ") + vk_result_name(r);
}

Status init_loader() {
    // volkInitialize is idempotent; it fails when libvulkan.so.1 cannot be opened.
    if (volkInitialize() != VK_SUCCESS)
        return Error{"no Vulkan loader found (libvulkan.so.1 missing)"};
    if (volkGetInstanceVersion() < VK_API_VERSION_1_3)
        return Error{"the Vulkan loader is older than 1.3"};
    return {};
}

Result<std::vector<DeviceReport>> probe_devices() {
    if (Status s = init_loader(); !s)
        return Error{s.error()};
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "vx probe";
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    if (VkResult res = vkCreateInstance(&ci, nullptr, &instance); res != VK_SUCCESS)
        return Error{instance_error(res)};
    // volk keeps instance-level pointers in globals: load ours, then give a live Context's back.
    const VkInstance previous = volkGetLoadedInstance();
    volkLoadInstanceOnly(instance);

    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> pds(n);
    vkEnumeratePhysicalDevices(instance, &n, pds.data());
    std::vector<DeviceReport> out;
    for (uint32_t i = 0; i < n; ++i)
        out.push_back(describe_device(pds[i], i));
    vkDestroyInstance(instance, nullptr);
    if (previous != VK_NULL_HANDLE)
        volkLoadInstanceOnly(previous);
    if (out.empty())
        return Error{missing_driver_message(std::getenv("VK_DRIVER_FILES"), std::getenv("VK_ICD_FILENAMES"))};
    return out;
}

Result<DeviceChoice> parse_device_choice(std::string_view text) {
    if (text == "auto" || text.empty())
        return DeviceChoice{};
    if (text == "cpu")
        return DeviceChoice{DeviceChoice::Kind::Cpu, 0};
    if (text == "gpu")
        return DeviceChoice{DeviceChoice::Kind::Gpu, 0};
    uint32_t index = 0;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
    if (ec != std::errc() || ptr != text.data() + text.size())
        return Error{"bad device choice '" + std::string(text) + "' (expected auto, cpu, gpu or an index)"};
    return DeviceChoice{DeviceChoice::Kind::Index, index};
}

static int auto_rank(const DeviceReport& d) {
    switch (d.type) {
    case DeviceType::Discrete: return 4;
    case DeviceType::Integrated: return 3;
    case DeviceType::Virtual: return 2;
    case DeviceType::Cpu: return 1;
    default: return 0;
    }
}

Result<uint32_t> choose_device(const std::vector<DeviceReport>& devices, DeviceChoice choice, bool need_present) {
    if (choice.kind == DeviceChoice::Kind::Index) {
        if (choice.index >= devices.size())
            return Error{"device index " + std::to_string(choice.index) + " out of range (" +
                         std::to_string(devices.size()) + " devices)"};
        if (!devices[choice.index].can_ray_trace())
            return Error{"device " + std::to_string(choice.index) + " (" + devices[choice.index].name +
                         ") cannot ray trace (needs Vulkan 1.3, KHR acceleration structures + RT "
                         "pipelines, float atomics and compute subgroup sums; `vx info` lists what "
                         "it lacks)"};
        if (need_present && !devices[choice.index].present)
            return Error{"device " + std::to_string(choice.index) + " (" + devices[choice.index].name +
                         ") cannot present to the window (needs VK_KHR_swapchain and a graphics queue that presents)"};
        return choice.index;
    }
    int best = -1, best_rank = -1;
    for (const DeviceReport& d : devices) {
        if (!d.can_ray_trace() || (need_present && !d.present))
            continue;
        if (choice.kind == DeviceChoice::Kind::Cpu && d.type != DeviceType::Cpu)
            continue;
        if (choice.kind == DeviceChoice::Kind::Gpu && d.type == DeviceType::Cpu)
            continue;
        if (auto_rank(d) > best_rank)
            best = int(d.index), best_rank = auto_rank(d);
    }
    if (best < 0)
        return Error{"no Vulkan device that can ray trace" + std::string(need_present ? " and present to the window" : "") +
                     std::string(choice.kind == DeviceChoice::Kind::Cpu   ? " on the CPU"
                                 : choice.kind == DeviceChoice::Kind::Gpu ? " on a GPU"
                                                                          : "") +
                     " (needs Vulkan 1.3, VK_KHR_acceleration_structure, VK_KHR_ray_tracing_pipeline, "
                     "VK_KHR_deferred_host_operations, bufferDeviceAddress)"};
    return uint32_t(best);
}

} // namespace vx::render
