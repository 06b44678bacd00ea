// Renderer::pipeline_report() (render/pipeline_report.h): what the driver made of each ray-tracing
// pipeline variant, the numbers behind "code a frame never runs still costs every ray".
#include <set>
#include <string>

#include "scene_util.h"

namespace vx::render {
namespace {

const Camera kHillsView = Camera::look_at({-6.5, 12.0, 9.5}, {2.0, 4.0, -2.0});

// Every variant is made and named once, each with its five groups' stacks, the hit group's in the
// closest-hit and any-hit columns and the others' in the general one.
TEST(PipelineReportTest, ListsEveryVariantWithItsGroupsStacks) {
    std::unique_ptr<Renderer> r = test::make_renderer({.pipeline_statistics = true});
    ASSERT_NE(r, nullptr);
    Result<PipelineReport> report = r->pipeline_report();
    ASSERT_TRUE(report) << report.error();
    EXPECT_EQ(report->device, r->device().name);
    ASSERT_EQ(report->variants.size(), 6u);
    std::set<std::string> names;
    for (const PipelineVariantReport& v : report->variants) {
        names.insert(v.name);
        ASSERT_EQ(v.stacks.size(), 5u) << v.name;
        for (const PipelineGroupStack& g : v.stacks)
            if (g.group == "hit")
                EXPECT_EQ(g.general, 0u) << v.name;
            else
                EXPECT_EQ(g.closest_hit + g.any_hit, 0u) << v.name << " " << g.group;
    }
    EXPECT_EQ(names.size(), 6u) << "each variant once";
    EXPECT_TRUE(names.contains("rt pipeline, opaque only")) << "the variant without see-through code";
    EXPECT_TRUE(names.contains("rt pipeline, emitter faces, probes"));
    const std::string text = format_pipeline_report(*report);
    for (const std::string& n : names)
        EXPECT_NE(text.find(n + "\n"), std::string::npos) << n;
    EXPECT_EQ(r->validation_errors(), 0u);
}

// Where the device keeps statistics, every variant lists executables, each with at least one
// statistic with a name and a value, and the text shows them; where it cannot, the report says
// why and lists none.
TEST(PipelineReportTest, ExecutablesCarryTheDriversStatisticsOrTheReportSaysWhyNot) {
    std::unique_ptr<Renderer> r = test::make_renderer({.pipeline_statistics = true});
    ASSERT_NE(r, nullptr);
    Result<PipelineReport> report = r->pipeline_report();
    ASSERT_TRUE(report) << report.error();
    if (!report->statistics_note.empty()) {
        for (const PipelineVariantReport& v : report->variants)
            EXPECT_TRUE(v.executables.empty()) << v.name;
        GTEST_SKIP() << "the device keeps no pipeline statistics: " << report->statistics_note;
    }
    const std::string text = format_pipeline_report(*report);
    for (const PipelineVariantReport& v : report->variants) {
        ASSERT_FALSE(v.executables.empty()) << v.name;
        for (const PipelineExecutable& e : v.executables) {
            ASSERT_FALSE(e.statistics.empty()) << v.name << " " << e.name;
            for (const PipelineStatistic& s : e.statistics) {
                EXPECT_FALSE(s.name.empty());
                EXPECT_NE(s.value, "?") << s.name;
                EXPECT_NE(text.find("    " + s.name + ": " + s.value + "\n"), std::string::npos) << s.name;
            }
        }
    }
    EXPECT_EQ(text.find("no executable statistics"), std::string::npos);
    EXPECT_EQ(r->validation_errors(), 0u);
}

// Not asked for: no executables, the note says so, and the stacks are still there.
TEST(PipelineReportTest, WithoutTheOptionTheReportSaysStatisticsWereNotAskedFor) {
    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    Result<PipelineReport> report = r->pipeline_report();
    ASSERT_TRUE(report) << report.error();
    EXPECT_NE(report->statistics_note.find("not asked for"), std::string::npos) << report->statistics_note;
    ASSERT_EQ(report->variants.size(), 6u);
    for (const PipelineVariantReport& v : report->variants) {
        EXPECT_TRUE(v.executables.empty()) << v.name;
        EXPECT_EQ(v.stacks.size(), 5u) << v.name;
    }
    EXPECT_NE(format_pipeline_report(*report).find("no executable statistics: not asked for"),
              std::string::npos);
    EXPECT_EQ(r->validation_errors(), 0u);
}

// Statistics kept but no executable listed is said in the note; one executable anywhere, or a note
// already there, leaves the note as it is. (On the H100 at 182a844 both statistics tests failed,
// the statistics test and CliRender.PipelineReportListsEveryVariant, and the variant test passed:
// what an empty list with no note gives.)
TEST(PipelineReportTest, NoExecutablesListedIsSaidInTheNote) {
    PipelineReport none{"gpu", {{"rt pipeline", {}, {}}, {"rt pipeline, probes", {}, {}}}, ""};
    note_missing_executables(none);
    EXPECT_EQ(none.statistics_note, "the driver lists no executables for ray tracing pipelines");
    EXPECT_NE(format_pipeline_report(none).find("no executable statistics: the driver lists no executables"),
              std::string::npos);
    PipelineReport one = none;
    one.statistics_note.clear();
    one.variants[1].executables.push_back({"raygen", "", 0, 32, {{"Register Count", "", "96"}}});
    note_missing_executables(one);
    EXPECT_EQ(one.statistics_note, "");
    EXPECT_NE(format_pipeline_report(one).find("    Register Count: 96\n"), std::string::npos);
    const std::string not_asked = "not asked for (ContextCreateInfo::pipeline_statistics)";
    PipelineReport asked{"cpu", {{"rt pipeline", {}, {}}}, not_asked};
    note_missing_executables(asked);
    EXPECT_EQ(asked.statistics_note, not_asked);
}

// A variant the device has no memory for: an error naming which, no abort; the renderer still
// renders with the variant it has, and a later report, with memory back, lists all six.
TEST(PipelineReportTest, AVariantWithoutMemoryIsAnErrorAndTheRendererGoesOn) {
    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    r->fail_allocations("rt pipeline, emitter faces");
    Result<PipelineReport> report = r->pipeline_report();
    ASSERT_FALSE(report);
    EXPECT_NE(report.error().find("out of memory for ray tracing pipeline variant 2 of 6"), std::string::npos)
        << report.error();
    r->fail_allocations("");
    test::load_meshes(*r, test::mesh_world(test::hills()));
    Result<RenderImage> img = r->try_render(test::daylight(1), kHillsView);
    EXPECT_TRUE(img) << img.error();
    report = r->pipeline_report();
    ASSERT_TRUE(report) << report.error();
    EXPECT_EQ(report->variants.size(), 6u);
    EXPECT_EQ(r->validation_errors(), 0u);
}

// A lost device: the report is an error, not an abort.
TEST(PipelineReportTest, ALostDeviceIsAnError) {
    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    test::load_meshes(*r, test::mesh_world(test::hills()));
    r->simulate_device_loss();
    EXPECT_FALSE(r->try_render(test::daylight(1), kHillsView));
    ASSERT_TRUE(r->device_lost());
    Result<PipelineReport> report = r->pipeline_report();
    ASSERT_FALSE(report);
    EXPECT_EQ(report.error(), "the device was lost");
}

} // namespace
} // namespace vx::render
