#pragma once
// Shared by the renderer tests: a lavapipe context with validation on, checked for 0 errors.

#include <cstdlib>
#include <memory>

#include <gtest/gtest.h>

#include "render/context.h"

namespace vx::render::test {

// lavapipe ("cpu") unless $VX_TEST_DEVICE names another choice (auto, gpu, an index).
inline DeviceChoice test_device_choice() {
    const char* env = std::getenv("VX_TEST_DEVICE");
    Result<DeviceChoice> c = parse_device_choice(env ? env : "cpu");
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
