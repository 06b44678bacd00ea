#include "render/context.h"

#include <cstring>

#include "render/device_probe_internal.h"
#include "render/present_window.h"
#include "world/base/log.h"

namespace vx::render {

static const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                       void* user) {
    auto* self = static_cast<Context*>(user);
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        self->m_validation_errors.fetch_add(1);
        VX_LOG_ERROR("vulkan: %s", data->pMessage);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        self->m_validation_warnings.fetch_add(1);
        VX_LOG_WARN("vulkan: %s", data->pMessage);
    }
    return VK_FALSE;
}

static bool layer_available(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const VkLayerProperties& l : layers)
        if (std::strcmp(l.layerName, name) == 0)
            return true;
    return false;
}

static bool instance_extension_available(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, exts.data());
    for (const VkExtensionProperties& e : exts)
        if (std::strcmp(e.extensionName, name) == 0)
            return true;
    return false;
}

Result<std::unique_ptr<Context>> Context::create(const ContextCreateInfo& info) {
    if (Status s = init_loader(); !s)
        return Error{s.error()};
    std::unique_ptr<Context> ctx(new Context());
    ctx->fail_allocations(info.fail_allocations);
    if (Status s = ctx->create_instance(info); !s)
        return Error{s.error()};
    if (Status s = ctx->create_surface(info); !s)
        return Error{s.error()};
    if (Status s = ctx->pick_device(info); !s)
        return Error{s.error()};
    if (Status s = ctx->create_device(info.pipeline_statistics); !s)
        return Error{s.error()};
    if (Status s = ctx->create_frames(); !s)
        return Error{s.error()};
    return ctx;
}

Status Context::create_instance(const ContextCreateInfo& info) {
    m_debug_utils = instance_extension_available(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    m_validation = info.validation && layer_available(kValidationLayer);
    if (info.validation && !m_validation)
        VX_LOG_WARN("validation requested but %s is not installed", kValidationLayer);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = info.app_name;
    app.pEngineName = "vx";
    app.apiVersion = VK_API_VERSION_1_3; // Debian's headers, loader and layers are 1.3.239 (lavapipe says 1.4).

    VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mci.pfnUserCallback = debug_callback;
    mci.pUserData = this;

    std::vector<const char*> exts, layers;
    if (m_debug_utils)
        exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (info.window) {
        Result<std::vector<const char*>> wsi = window_instance_extensions();
        if (!wsi)
            return Error{wsi.error()};
        exts.insert(exts.end(), wsi->begin(), wsi->end());
    }
    if (m_validation)
        layers.push_back(kValidationLayer);
    const VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pNext = m_debug_utils ? &mci : nullptr; // Also reports problems of vkCreate/DestroyInstance.
    if (m_validation && info.sync_validation) {
        m_sync_validation = true;
        features.pNext = ci.pNext;
        ci.pNext = &features;
    }
    ci.pApplicationInfo = &app;
    ci.enabledExtensionCount = uint32_t(exts.size());
    ci.ppEnabledExtensionNames = exts.data();
    ci.enabledLayerCount = uint32_t(layers.size());
    ci.ppEnabledLayerNames = layers.data();
    if (VkResult r = vkCreateInstance(&ci, nullptr, &m_instance); r != VK_SUCCESS)
        return Error{instance_error(r)};
    volkLoadInstance(m_instance);
    // Out of host memory (it was a VK_CHECK abort): an error, not a context whose validation
    // errors would go uncounted.
    if (m_debug_utils && create_call("vkCreateDebugUtilsMessengerEXT", [&] {
            return vkCreateDebugUtilsMessengerEXT(m_instance, &mci, nullptr, &m_messenger);
        }) != VK_SUCCESS)
        return Error{"cannot create the Vulkan instance's debug messenger: " + m_last_create_failure};
    return {};
}

Status Context::create_surface(const ContextCreateInfo& info) {
    if (!info.window)
        return {};
    Result<VkSurfaceKHR> surface = create_window_surface(m_instance, info.window);
    if (!surface)
        return Error{surface.error()};
    m_surface = *surface;
    m_window = info.window;
    return {};
}

// A queue family with graphics (vkCmdBlitImage needs it) and compute that presents to the
// surface, on a device with VK_KHR_swapchain.
bool Context::can_present(VkPhysicalDevice pd, uint32_t* family) {
    if (!device_has_extension(pd, VK_KHR_SWAPCHAIN_EXTENSION_NAME))
        return false;
    // Frames are blitted into the swapchain's images: a surface whose images cannot be a copy's
    // destination cannot show them here (the spec guarantees only COLOR_ATTACHMENT usage).
    VkSurfaceCapabilitiesKHR caps;
    if (vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, m_surface, &caps) != VK_SUCCESS ||
        !(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return false;
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> qf(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, qf.data());
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; i < n; ++i) {
        VkBool32 supported = VK_FALSE;
        if ((qf[i].queueFlags & need) != need)
            continue;
        // Out of memory or a lost surface (it was a VK_CHECK abort): this family cannot present;
        // pick_device's error names the call.
        if (create_call("vkGetPhysicalDeviceSurfaceSupportKHR", [&] {
                return vkGetPhysicalDeviceSurfaceSupportKHR(pd, i, m_surface, &supported);
            }) == VK_SUCCESS && supported) {
            *family = i;
            return true;
        }
    }
    return false;
}

Status Context::pick_device(const ContextCreateInfo& info) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(m_instance, &n, nullptr);
    std::vector<VkPhysicalDevice> pds(n);
    vkEnumeratePhysicalDevices(m_instance, &n, pds.data());
    std::vector<DeviceReport> reports;
    std::vector<uint32_t> present_family(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        reports.push_back(describe_device(pds[i], i));
        if (m_surface)
            reports.back().present = can_present(pds[i], &present_family[i]);
    }
    Result<uint32_t> chosen = choose_device(reports, info.device, m_surface != VK_NULL_HANDLE);
    if (!chosen && !m_last_create_failure.empty())
        return Error{chosen.error() + " (" + m_last_create_failure + ")"};
    if (!chosen)
        return Error{chosen.error()};
    m_pd = pds[*chosen];
    m_report = reports[*chosen];

    VkPhysicalDeviceVulkan13Properties p13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES};
    m_as_props = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR, &p13};
    m_rt_props = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR, &m_as_props};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &m_rt_props};
    vkGetPhysicalDeviceProperties2(m_pd, &props);
    m_rt_props.pNext = nullptr;
    m_as_props.pNext = nullptr;
    m_max_buffer_size = p13.maxBufferSize;
    m_limits = props.properties.limits;
    if (m_surface) {
        m_queue_family = present_family[*chosen];
        return {};
    }

    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(m_pd, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> qf(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(m_pd, &qn, qf.data());
    for (uint32_t i = 0; i < qn; ++i)
        if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            m_queue_family = i;
            return {};
        }
    return Error{"device " + m_report.name + " has no compute queue"};
}

// Whether `pd` can keep pipeline statistics (the extension and its one feature), else why not.
static std::string statistics_missing(VkPhysicalDevice pd) {
    if (!device_has_extension(pd, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME))
        return "the device does not offer " VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR exec{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &exec};
    vkGetPhysicalDeviceFeatures2(pd, &f2);
    return exec.pipelineExecutableInfo ? "" : "the device does not support pipelineExecutableInfo";
}

Status Context::create_device(bool pipeline_statistics) {
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
    atomics.shaderBufferFloat32AtomicAdd = VK_TRUE; // The light cache (device_probe.h).
    VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR, &atomics};
    rt.rayTracingPipeline = VK_TRUE;
    VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR, &rt};
    as.accelerationStructure = VK_TRUE;
    VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES, &as};
    v13.synchronization2 = VK_TRUE;
    v13.dynamicRendering = VK_TRUE; // The raster pipeline (core in 1.3).
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &v13};
    v12.bufferDeviceAddress = VK_TRUE;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
    f2.features.shaderInt64 = VK_TRUE;

    std::vector<const char*> exts = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                     VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
                                     VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
                                     VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME};
    if (m_surface)
        exts.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR exec{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    if (pipeline_statistics) {
        m_statistics_note = statistics_missing(m_pd);
        if (m_statistics_note.empty()) {
            exts.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
            exec.pipelineExecutableInfo = VK_TRUE;
            exec.pNext = atomics.pNext;
            atomics.pNext = &exec;
        }
    }
    const float priority = 1.f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = m_queue_family;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo ci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &f2};
    ci.queueCreateInfoCount = 1;
    ci.pQueueCreateInfos = &qci;
    ci.enabledExtensionCount = uint32_t(exts.size());
    ci.ppEnabledExtensionNames = exts.data();
    // Out of memory, too many devices, a driver that fails to initialise: the machine's state, an
    // error for Renderer::create (a missing feature was refused when the device was chosen).
    if (const VkResult made = vkCreateDevice(m_pd, &ci, nullptr, &m_device); made != VK_SUCCESS) {
        m_device = VK_NULL_HANDLE;
        return Error{std::string("cannot create the Vulkan device on ") + m_report.name + ": vkCreateDevice returned " +
                     vk_result_name(made)};
    }
    volkLoadDevice(m_device);
    m_pipeline_statistics = exec.pipelineExecutableInfo == VK_TRUE;
    vkGetDeviceQueue(m_device, m_queue_family, 0, &m_queue);
    set_name(m_device, VK_OBJECT_TYPE_DEVICE, "vx device");
    set_name(m_queue, VK_OBJECT_TYPE_QUEUE, "vx queue");
    m_allocator = std::make_unique<GpuAllocator>(m_pd, m_device, 64ull << 20, m_debug_utils, &m_faults);
    return {};
}

void Context::set_name(VkObjectType type, uint64_t handle, const char* name) const {
    if (!m_debug_utils || !vkSetDebugUtilsObjectNameEXT || handle == 0)
        return;
    VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    ni.objectType = type;
    ni.objectHandle = handle;
    ni.pObjectName = name;
    (void)vkSetDebugUtilsObjectNameEXT(m_device, &ni); // Out of host memory: only the name is missing.
}

Context::~Context() {
    if (m_device) {
        wait_idle();
        for (Frame& f : m_frames) {
            vkDestroyFence(m_device, f.fence, nullptr);
            vkDestroyCommandPool(m_device, f.pool, nullptr);
        }
        vkDestroyFence(m_device, m_one_shot_fence, nullptr);
        vkDestroyCommandPool(m_device, m_one_shot_pool, nullptr);
        m_allocator.reset();
        vkDestroyDevice(m_device, nullptr);
    }
    if (m_surface)
        vkDestroySurfaceKHR(m_instance, m_surface, nullptr);
    if (m_messenger)
        vkDestroyDebugUtilsMessengerEXT(m_instance, m_messenger, nullptr);
    if (m_instance)
        vkDestroyInstance(m_instance, nullptr);
}

} // namespace vx::render
