#pragma once
// Probe helpers shared by device_probe.cpp and context.cpp. Thread-safe.

#include "render/device_probe.h"
#include "render/vk_common.h"

namespace vx::render {

// Loads libvulkan through volk; an error when no loader (or one older than 1.3) exists.
Status init_loader();
// "vkCreateInstance failed: ..." for `r`; for VK_ERROR_INCOMPATIBLE_DRIVER, missing_driver_message()
// of this process's environment.
std::string instance_error(VkResult r);
// Whether physical device `pd` offers device extension `name` (instance-level functions loaded).
bool device_has_extension(VkPhysicalDevice pd, const char* name);
// The report of one physical device (instance-level functions must be loaded).
DeviceReport describe_device(VkPhysicalDevice pd, uint32_t index);

} // namespace vx::render
