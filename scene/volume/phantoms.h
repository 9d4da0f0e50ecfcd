#pragma once
// Test volumes made in code: deterministic, no download, with geometry known exactly so that tests
// of every kernel can check a rendered image against it.
//
// Coordinates below are voxel indices: voxel (i, j, k) is the point (i, j, k), as the renderers place
// it (world position = index * spacing, spacing 1 here). Values are 0..255 with source type uint8
// unless stated, but samples are not rounded: smooth boundaries keep fractional values.

#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <span>
#include <string_view>

namespace pp5 {

// n^3 voxels. A ball of value 200 in 0, centred on the grid centre c = ((n-1)/2, (n-1)/2, (n-1)/2)
// with radius r = radius_fraction * n voxels. The edge is a linear ramp one voxel wide in the
// distance d from c: value = 200 * clamp(r + 0.5 - d, 0, 1). So the iso-surface of value 100 is
// exactly the sphere of radius r, and the voxels above 100 are those with d < r.
// Throws std::invalid_argument if n < 1 or radius_fraction <= 0.
Volume make_sphere_phantom(int n, float radius_fraction = 0.35f);

// The 3D checker box of Yuan et al. 2003 (100^3, all 1,000,000 voxels non-empty): cubes of `cell`
// voxels alternating between 200 and 100. Voxel (x, y, z) is 200 when x/cell + y/cell + z/cell
// (integer division) is even, else 100. Edges are sharp, as in the paper, to show aliasing.
// Throws std::invalid_argument if n < 1 or cell < 1.
Volume make_checker_box_phantom(int n = 100, int cell = 10);

// A layered head in the spirit of the Shepp-Logan phantom, in 3D with a skull shell. n^3 voxels,
// axes x left-right, y back-front, z feet-head; nested ellipsoids about the grid centre, semi-axes in
// units of n/2:
//   skin     (0.70, 0.88, 0.80)  value  60, the layer outside the skull
//   skull    (0.64, 0.82, 0.74)  value 220, a shell down to the brain
//   brain    (0.56, 0.74, 0.66)  value 110
//   ventricles: two ellipsoids at (+-0.11, 0.02, 0.08) from the centre, semi-axes (0.07, 0.24, 0.12),
//            value 30
// outside 0. Every boundary is a one-voxel linear ramp. Throws std::invalid_argument if n < 1.
Volume make_head_phantom(int n);

// Every voxel `value`, source type Float32: for closed-form tests.
Volume make_constant_volume(glm::ivec3 dims, float value);

// By name, for scenarios and the CLI: "sphere", "checker-box", "head", each n^3 (checker box with
// 10-voxel cells). Throws InputError(field "phantom" or "size") for an unknown name, listing the known
// ones, or an n outside 1..1024.
Volume make_phantom(std::string_view name, int n);
std::span<const std::string_view> phantom_names();

}  // namespace pp5
