// A program that does not link vx_vdb (this test binary) carries no OpenVDB, and a VDB world
// source then says what to link instead of failing obscurely. The VDB world itself is tested in
// facade_test.cpp, whose binary links vx_vdb.
#include <gtest/gtest.h>

#include <vx/vx.h>

#include "world/store/store_open.h"

TEST(VdbSource, WithoutVxVdbLinkedSaysWhatToLink) {
    ASSERT_EQ(vx::world::vdb_store_opener(), nullptr);
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::vdb("world.vdb");
    auto engine = vx::Engine::create(info);
    ASSERT_FALSE(engine);
    EXPECT_NE(engine.error().find("find_package(vx COMPONENTS vdb)"), std::string::npos) << engine.error();
    EXPECT_NE(engine.error().find("vx::vdb"), std::string::npos) << engine.error();
}
