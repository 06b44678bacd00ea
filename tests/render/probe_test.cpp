#include <cstdlib>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "render/device_probe.h"
#include "render_test_util.h"

namespace vx::render {
namespace {

TEST(DeviceProbe, FindsARayTracingCpuDevice) {
    if (std::getenv("VX_TEST_DEVICE"))
        GTEST_SKIP() << "VX_TEST_DEVICE set: not on lavapipe";
    Result<std::vector<DeviceReport>> devices = probe_devices();
    ASSERT_TRUE(devices.ok()) << devices.error();
    ASSERT_FALSE(devices->empty());
    bool found = false;
    for (const DeviceReport& d : *devices) {
        EXPECT_FALSE(d.name.empty());
        if (d.type == DeviceType::Cpu && d.can_ray_trace()) {
            found = true;
            EXPECT_TRUE(d.acceleration_structure && d.ray_tracing_pipeline && d.deferred_host_operations &&
                        d.buffer_device_address && d.float_atomic_add && d.compute_subgroup_sums);
            EXPECT_GE(d.api_version_string(), std::string("1.3"));
            EXPECT_GE(d.max_buffer_size, uint64_t(1) << 30); // Vulkan 1.3's minimum maxBufferSize: 2^30.
            EXPECT_GT(d.device_memory, 0u);
        }
    }
    EXPECT_TRUE(found) << "lavapipe with ray tracing expected (VK_DRIVER_FILES)";
}

DeviceReport fake(uint32_t index, DeviceType type, bool rt) {
    DeviceReport d;
    d.index = index;
    d.name = "fake";
    d.type = type;
    d.api_version = (1u << 22) | (3u << 12); // 1.3.0
    d.acceleration_structure = d.ray_tracing_pipeline = d.deferred_host_operations = rt;
    d.buffer_device_address = d.float_atomic_add = d.compute_subgroup_sums = true;
    return d;
}

TEST(DeviceProbe, ChoicePrefersRayTracingDiscreteGpu) {
    const std::vector<DeviceReport> devs = {fake(0, DeviceType::Cpu, true), fake(1, DeviceType::Integrated, false),
                                            fake(2, DeviceType::Discrete, true)};
    EXPECT_EQ(*choose_device(devs, DeviceChoice{}), 2u);
    EXPECT_EQ(*choose_device(devs, *parse_device_choice("cpu")), 0u);
    EXPECT_EQ(*choose_device(devs, *parse_device_choice("gpu")), 2u);
    EXPECT_EQ(*choose_device(devs, *parse_device_choice("0")), 0u);
    const Result<uint32_t> cannot = choose_device(devs, *parse_device_choice("1"));
    ASSERT_FALSE(cannot.ok()); // Cannot ray trace: the error says where to see why.
    EXPECT_NE(cannot.error().find("`vx info` lists what it lacks"), std::string::npos) << cannot.error();
    EXPECT_FALSE(choose_device(devs, *parse_device_choice("7")).ok()); // Out of range.
    EXPECT_FALSE(parse_device_choice("fast").ok());
    EXPECT_FALSE(parse_device_choice("1x").ok());
}

TEST(DeviceProbe, NoRayTracingDeviceIsAClearError) {
    const std::vector<DeviceReport> devs = {fake(0, DeviceType::Discrete, false)};
    Result<uint32_t> r = choose_device(devs, DeviceChoice{});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("ray trace"), std::string::npos);
}

TEST(DeviceProbe, RayTracingNeedsFloatAtomics) {
    DeviceReport d = fake(0, DeviceType::Discrete, true);
    d.float_atomic_add = false; // The light cache's sums are compiled into the ray generation.
    EXPECT_FALSE(d.can_ray_trace());
}

TEST(DeviceProbe, RayTracingNeedsComputeSubgroupSums) {
    DeviceReport d = fake(0, DeviceType::Discrete, true);
    EXPECT_TRUE(d.can_ray_trace());
    d.compute_subgroup_sums = false; // The light cache's gather pass sums a subgroup's hits.
    EXPECT_FALSE(d.can_ray_trace());
}

TEST(DeviceProbe, ApiVersionRequiresVulkan13) {
    DeviceReport d = fake(0, DeviceType::Discrete, true);
    d.api_version = (1u << 22) | (2u << 12);
    EXPECT_FALSE(d.can_ray_trace());
}

// A missing driver names the driver files looked for, not VK_ERROR_INCOMPATIBLE_DRIVER. The
// environment is put back afterwards: run in one process (the test binary alone, not ctest), every
// later test found no driver.
TEST(DeviceProbe, MissingDriverNamesTheFilesLookedFor) {
    struct Restore {
        std::optional<std::string> was;
        Restore() {
            if (const char* v = std::getenv("VK_DRIVER_FILES"))
                was = v;
        }
        ~Restore() { was ? setenv("VK_DRIVER_FILES", was->c_str(), 1) : unsetenv("VK_DRIVER_FILES"); }
    } restore;
    ASSERT_EQ(setenv("VK_DRIVER_FILES", "/nonexistent/vx_no_driver.json", 1), 0);
    Result<std::vector<DeviceReport>> devices = probe_devices();
    ASSERT_FALSE(devices.ok());
    EXPECT_NE(devices.error().find("no Vulkan driver found"), std::string::npos) << devices.error();
    EXPECT_NE(devices.error().find("VK_DRIVER_FILES=/nonexistent/vx_no_driver.json"), std::string::npos)
        << devices.error();
    EXPECT_NE(devices.error().find("missing: /nonexistent/vx_no_driver.json"), std::string::npos) << devices.error();
    EXPECT_EQ(devices.error().find("VK_ERROR"), std::string::npos) << devices.error();

    const std::string legacy = missing_driver_message(nullptr, "/a.json:/b.json");
    EXPECT_NE(legacy.find("VK_ICD_FILENAMES=/a.json:/b.json (missing: /a.json, /b.json)"), std::string::npos) << legacy;
    const std::string both = missing_driver_message("/x.json", "/a.json"); // The loader prefers VK_DRIVER_FILES.
    EXPECT_NE(both.find("VK_DRIVER_FILES=/x.json"), std::string::npos) << both;
    const std::string none = missing_driver_message(nullptr, nullptr);
    EXPECT_NE(none.find("/usr/share/vulkan/icd.d"), std::string::npos) << none;
}

using ContextTest = test::RenderTest;

TEST_F(ContextTest, CreatesHeadlessRayTracingDevice) {
    if (!std::getenv("VX_TEST_DEVICE")) {
        EXPECT_EQ(m_ctx->report().type, DeviceType::Cpu);
    }
    const auto& rt = m_ctx->rt_properties();
    EXPECT_GT(rt.shaderGroupHandleSize, 0u);
    EXPECT_GT(rt.shaderGroupBaseAlignment, 0u);
    EXPECT_GT(m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment, 0u);
    // Probing while a context is alive leaves the context's entry points usable.
    ASSERT_TRUE(probe_devices().ok());
    // Frames cycle without errors.
    for (int i = 0; i < 3; ++i) {
        m_ctx->begin_frame();
        m_ctx->end_frame();
    }
    EXPECT_EQ(m_ctx->frame_number(), 3u);
}

} // namespace
} // namespace vx::render
