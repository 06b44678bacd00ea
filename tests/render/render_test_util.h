#pragma once
// Shared by the renderer tests: a lavapipe context with validation on, checked for 0 errors.

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string_view>

#include <gtest/gtest.h>
#include <vx/log.h>

#include "render/context.h"
#include "tests/test_device.h"

namespace vx::render::test {

// tests/test_device.h's device, parsed.
inline DeviceChoice test_device_choice() {
    Result<DeviceChoice> c = parse_device_choice(vx::test::test_device());
    EXPECT_TRUE(c.ok()) << "bad VX_TEST_DEVICE";
    return c.ok() ? *c : DeviceChoice{DeviceChoice::Kind::Cpu, 0};
}

inline std::unique_ptr<Context> make_test_context() {
    ContextCreateInfo ci;
    ci.validation = true;
    ci.sync_validation = std::getenv("VX_SYNC_VALIDATION") != nullptr;
    ci.device = test_device_choice();
    ci.app_name = "vx_render_tests";
    Result<std::unique_ptr<Context>> ctx = Context::create(ci);
    if (!ctx) {
        ADD_FAILURE() << "no context: " << ctx.error();
        return nullptr;
    }
    EXPECT_TRUE((*ctx)->validation_enabled()) << "the validation layer must be installed for these tests";
    return std::move(*ctx);
}

// Counts the validation layer's errors logged while it lives, also those a Context logs as it is
// destroyed (leaked objects), which Context::validation_errors() can no longer be asked for.
// Lines still go to stderr. One at a time (it owns the process's log handler).
class LayerErrorCounter {
public:
    LayerErrorCounter() {
        set_log_handler([this](LogLevel level, std::string_view line) {
            if (level == LogLevel::Error && line.starts_with("vulkan:"))
                ++m_errors;
            std::fprintf(stderr, "%.*s\n", int(line.size()), line.data());
        });
    }
    ~LayerErrorCounter() { set_log_handler({}); }
    LayerErrorCounter(const LayerErrorCounter&) = delete;
    LayerErrorCounter& operator=(const LayerErrorCounter&) = delete;
    int errors() const { return m_errors.load(); }

private:
    std::atomic<int> m_errors{0};
};

// Fixture: a context per test; fails the test when the validation layer reported an error.
class RenderTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_ctx = make_test_context();
        ASSERT_NE(m_ctx, nullptr);
    }
    void TearDown() override {
        if (m_ctx) {
            m_ctx->wait_idle();
            EXPECT_EQ(m_ctx->validation_errors(), 0u);
        }
    }
    std::unique_ptr<Context> m_ctx;
};

} // namespace vx::render::test
