#pragma once
// Stages 4 and 5 of Levoy's pipeline: resample the shaded volume along rays and composite front to
// back. Any producer of voxel colours and opacities (this renderer's shade_voxels, or the simulated
// pixel processors in fixed point) feeds the same compositor.
//
// Per pixel, one ray through the pixel centre (camera.h). Samples at the centres of equal intervals of
// `sample_step` voxels (a voxel being the smallest of the three spacings), starting where the ray enters
// the box from voxel 0 to voxel dims-1 (ray_march.h). At each sample, colour and opacity are
// interpolated trilinearly and separately from the eight voxels around it (Levoy's order: shade and
// classify at the voxels, then resample; colours are not weighted by opacity), then
//   alpha' = 1 - (1 - alpha)^sample_step              (opacity is per voxel of path; exact for step 1)
//   C += (1 - A) alpha' c,   A += (1 - A) alpha'      (front to back)
// and the ray stops once A >= termination_opacity (if early_termination). The background shows
// through what is left: pixel = (C + (1 - A) background, A) — rgb is the picture as seen (the volume
// over the background), alpha the ray's accumulated opacity.
//
// Empty space is skipped exactly (occupancy_grid.h): the same samples at the same positions, so the
// image is bit-identical with skipping on or off; only the counters differ.

#include "scene/reference/occupancy_grid.h"
#include "scene/reference/shaded_volume.h"
#include "scene/render/camera.h"
#include "scene/render/image.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace pp5 {

struct CompositeSettings {
    int width = 512;
    int height = 512;
    float sample_step = 1.0f;  // voxels of the smallest spacing between samples; > 0
    bool early_termination = true;
    float termination_opacity = 0.95f;  // Levoy's 1 - epsilon, epsilon about 0.05; in (0, 1]
    glm::vec3 background{0.0f};
    bool skip_empty_space = true;

    bool operator==(const CompositeSettings&) const = default;
};

// Throws pp5::InputError (field "render.*") for an image size outside [1, 16384], a non-positive or
// non-finite sample step (or one below 1/1000 voxel), a termination opacity outside (0, 1], or a
// non-finite background.
void validate_composite_settings(const CompositeSettings& settings);

// Work counters: integers, identical at any thread count.
struct CompositeStats {
    std::uint64_t rays = 0;             // pixels
    std::uint64_t rays_hit = 0;         // rays that took at least one sample position in the volume
    std::uint64_t samples = 0;          // samples resampled and composited
    std::uint64_t samples_skipped = 0;  // samples in empty blocks, known transparent, not computed
    std::uint64_t rays_terminated = 0;  // rays stopped by early termination

    CompositeStats& operator+=(const CompositeStats& other);
    bool operator==(const CompositeStats&) const = default;
};

// Composites with an occupancy grid built here from the voxels' alpha.
Image composite(const ShadedVolume& volume, const Camera& camera, const CompositeSettings& settings,
                CompositeStats* stats = nullptr);
// The same with a grid built beforehand (occupancy_from_opacity or occupancy_from_alpha), for animation.
Image composite(const ShadedVolume& volume, const OccupancyGrid& occupancy, const Camera& camera,
                const CompositeSettings& settings, CompositeStats* stats = nullptr);

}  // namespace pp5
