#pragma once
// Ray casting through a PERM, and the work it asks of Pixel-planes 5. Rays and samples are the
// reference renderer's (scene/reference/ray_march.h): front to back, exact empty-space leaping over
// 4^3 blocks without a candidate cell, early termination. At a sample the GP takes the cell's record
// (fetched once through its cache when the ray enters the cell), looks the nearest quantized density
// and gradient up, classifies, shades and composites there, as the paper's renderer does.
//
// With perm.shading = pp (a PermRecordShading), the sample instead reads the colour and opacity the
// PPs left at its density position, and the GP only depth-cues it.
//
// The GPs take the picture in screen tiles (keys skewed row by row, as Levoy's kernel deals them);
// a tile's rays are items whose steps are the samples up to each new cell and that cell's fetch.

#include "kernels/perm/perm_record_shading.h"
#include "kernels/perm/perm_settings.h"
#include "kernels/perm/perm_structure.h"
#include "scene/reference/occupancy_grid.h"
#include "scene/render/camera.h"
#include "scene/render/classification.h"
#include "scene/render/image.h"
#include "scene/render/shading.h"
#include "sim/timing/recorded_work.h"

#include <cstdint>
#include <functional>
#include <memory>

namespace pp5 {

struct PermCastCounts {
    std::uint64_t rays = 0;
    std::uint64_t rays_terminated = 0;
    std::uint64_t samples = 0;        // in candidate cells: looked up
    std::uint64_t empty_samples = 0;  // in cells that are no candidate
    std::uint64_t leaped_samples = 0;
    std::uint64_t cell_fetches = 0;     // cells a ray entered (fetches through the GP's cache)
    std::uint64_t carried_lookups = 0;  // paper rule: a digit carried into the next axis

    PermCastCounts& operator+=(const PermCastCounts& other);
};

struct PermCastSettings {
    int width = 256, height = 256;
    float sample_step = 1.0f;
    float termination_opacity = 0.95f;
    glm::vec3 background{0.0f};
};

struct PermFrame {
    Image image;
    PermCastCounts counts;
    GpPhase work;  // the "ray_casting" phase
};

class PermRayCaster {
public:
    // `renderer_of_cell` says which renderer's backing store holds a candidate's record; null when the
    // structure sits in every GP's memory (no fetches). `shaded`, when given, holds what the PPs made
    // of the records, and must outlive the caster.
    PermRayCaster(const PermStructure& structure, glm::vec3 spacing, const PermSettings& settings,
                  std::function<std::uint32_t(glm::ivec3)> renderer_of_cell, const PermRecordShading* shaded = nullptr);
    PermFrame cast(const Classification& classification, const ColorMap& colors, const PhongLighting& lighting,
                   const Camera& camera, const PermCastSettings& settings) const;
    // What every GP holds to cast, wherever the records live: the occupancy distance map it leaps
    // empty space with, a byte a block (distances reach OccupancyGrid::kMaxDistance).
    std::uint64_t distance_map_bytes() const { return occupancy_.block_count(); }

private:
    const PermStructure* structure_;
    glm::vec3 spacing_;
    PermSettings settings_;
    OccupancyGrid occupancy_;
    const PermRecordShading* shaded_;
    std::shared_ptr<const BlockDirectory> records_;       // null: no fetches
    std::shared_ptr<const BlockDirectory> cued_records_;  // PP-shaded records with their densities
};

}  // namespace pp5
