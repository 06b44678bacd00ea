#pragma once
// VDB inputs the tests write themselves with OpenVDB, so a clone without shared/data/vdb still
// runs every test that does not need a file from another tool. Each is written once per process
// into a temporary folder. Not thread-safe (tests call it from their one thread).

#include <string>

namespace vx::vdb::test {

enum class TestFile {
    FogSphere,      // "density", fog volume, background 0: a ball of radius 12 voxels at the origin
                    // (active voxels -12..12 per axis), density 1 - |p| / 12 rising to 1 at the centre.
    LevelSetSphere, // "ls_sphere", level set, voxel 0.05, background 0.15 (3 voxels): the sphere of
                    // radius 60 voxels at the origin, value (|p| - 60) * 0.05 in the band, the
                    // interior inactive at -0.15 (pruned to tiles), as OpenVDB's own level sets.
    ThreeDensities, // Three fog grids all named "density" (index 0, 1, 2): balls of radius 6, 9 and
                    // 4 voxels at (0,0,0), (0,-4,1) and (20,0,0); the second spans (-9,-13,-8)..(9,5,10).
    ColourField,    // "Cd", a vec3s grid (not a scalar: import refuses it), 4³ active voxels.
    EmptyFog,       // "density", a fog volume with no active voxel (import refuses: empty).
    Truncated,      // FogSphere cut to half its bytes (the reader fails: "cannot read").
    FloatBlocks,    // A float grid named "blocks" (a vx world's name, not its value type), 2³ voxels.
    InstancedBlocks, // Int32 grids "terrain" and "blocks" sharing one tree: OpenVDB writes "blocks"
                     // as an instance of "terrain" (no tree of its own).
};

// Absolute path of the file, written on first use; empty (with a test failure) if writing failed.
const std::string& test_file(TestFile which);

} // namespace vx::vdb::test
