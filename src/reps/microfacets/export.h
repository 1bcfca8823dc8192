// `standin export` of microfacets (export.cpp): the octree's voxels at one level as cut-out squares
// in their surface's plane (the default), or as a closed, vertex-coloured mesh of their faces. Declared here rather than in microfacets.h so that the export
// stays one file and one registry line (representation.cpp).
#pragma once

#include "reps/microfacets/voxels.h"

#include <standin/export.h>
#include <standin/options.h>

#include <cstdint>
#include <vector>

namespace standin::microfacets {

std::vector<OptionSpec> export_options();
Result<ExportScene> export_scene(const Package& package, const Options& options);

// One exposed face of a voxel: `voxel` indexes the level's sorted codes, `side` is 0..5 for
// +x, -x, +y, -y, +z, -z.
struct VoxelFace {
    std::uint32_t voxel = 0;
    int side = 0;
};

// The faces of the voxels at `level` that border space reachable from outside the grid: faces
// between two occupied voxels are culled, and so are faces towards cavities the voxels enclose
// (the inside of a voxelised closed surface), so the faces form closed surfaces. In code order,
// sides ascending.
std::vector<VoxelFace> exposed_faces(const Octree& tree, int level);

} // namespace standin::microfacets
