#pragma once
// The GPs' functional work in Levoy's design: cast rays through the shaded volume the PPs hold,
// resample and composite front to back, skip empty space with the pyramid of binary volumes and stop
// opaque rays early; and record, for the timing layer, what each ray did in the machine's terms (the
// blocks of voxels it needed, in order, and the work between them).
//
// The samples are the reference compositor's (scene/reference/composite.h): the same positions, the
// same trilinear interpolation and the same front-to-back rule, so a ray that skips nothing gives the
// reference's pixel exactly. Pyramid skipping is exact: it passes over samples whose level-0 cell is
// empty (kernels/levoy/binary_pyramid.h), and tests every sample it does not pass over.
//
// Traversal (position driven): at sample k the ray tests its level-0 cell; if the cell is empty it
// climbs while the enclosing cell one level up is empty too, then leaps to the first sample beyond the
// largest empty cell it found. Each cell tested is one pyramid step.

#include "kernels/levoy/binary_pyramid.h"
#include "kernels/levoy/voxel_blocks.h"
#include "kernels/shared/pp_volume/shaded_codes.h"
#include "scene/render/camera.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pp5 {

struct RayCastSettings {
    int width = 512;
    int height = 512;
    float sample_step = 1.0f;
    bool early_termination = true;
    float termination_opacity = 0.95f;
    glm::vec3 background{0.0f};
    bool pyramid_skipping = true;
};

// The work between two block look-ups of one ray: `samples` resampled and `pyramid_steps` taken
// since the previous look-up, then a look-up of `block`.
struct BlockTouch {
    std::uint32_t block = 0;
    std::uint32_t samples = 0;
    std::uint32_t pyramid_steps = 0;
};

struct RayWork {
    std::uint32_t pixel = 0;        // y * width + x
    std::uint32_t first_touch = 0;  // into CastBatch::touches
    std::uint32_t touch_count = 0;
    std::uint32_t tail_samples = 0;  // after the last look-up
    std::uint32_t tail_pyramid_steps = 0;
    std::uint32_t samples = 0;  // in all
    std::uint32_t samples_skipped = 0;
    std::uint32_t pyramid_steps = 0;
    std::uint32_t first_sample = 0;  // the first sample not known empty (the depth a depth buffer keeps)
    bool hit = false;                // the ray meets the volume
    bool terminated = false;
};

struct CastBatch {
    std::vector<glm::vec4> colors;  // per ray: rgb over the background, and the ray's opacity
    std::vector<RayWork> rays;      // in the order asked for
    std::vector<BlockTouch> touches;
};

class RayCaster {
public:
    // Holds references to its inputs. The pyramid must be of the same volume.
    RayCaster(const ShadedCodes& volume, const BinaryPyramid& pyramid, const VoxelBlocks& blocks, const Camera& camera,
              const RayCastSettings& settings);

    // Casts the rays through the centres of `pixels`, in parallel; the result does not depend on the
    // thread count. `start_samples`, when given (one per pixel of the image), says where each ray may
    // start: every sample before it is known to be empty (a depth buffer from an earlier frame).
    CastBatch cast(std::span<const std::uint32_t> pixels, std::span<const std::uint32_t> start_samples = {}) const;

private:
    void cast_one(std::uint32_t pixel, std::uint32_t start, glm::vec4& color, RayWork& work,
                  std::vector<BlockTouch>& touches) const;

    const ShadedCodes& volume_;
    const BinaryPyramid& pyramid_;
    const VoxelBlocks& blocks_;
    RayCastSettings settings_;
    PixelRays rays_;
};

}  // namespace pp5
