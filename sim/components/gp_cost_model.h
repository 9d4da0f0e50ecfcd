#pragma once
// What a graphics processor's work costs: the i860 by operation class. Floating-point classes are
// counted in flops and run at the GP's sustained rate (gp.sustained_mflops, Levoy's 20 MFLOPS); control
// classes (look-ups, messages, context switches) are counted in GP clock cycles. None of these numbers
// is published: each default is an operation count of the obvious implementation, documented with the
// parameter, and the calibration fits them. A cost is kept in picoseconds so that sums are exact.

#include "sim/core/config.h"
#include "sim/core/param.h"
#include "sim/core/time.h"

#include <cstdint>

namespace pp5 {

struct GpCostModel {
    // Floating-point work, per operation.
    Tick ray_setup = 0;         // a ray's origin, direction and entry into the volume
    Tick sample_step = 0;       // advance to the next sample and find its cell
    Tick interpolation = 0;     // trilinear interpolation of colour and opacity
    Tick compositing = 0;       // front-to-back compositing of one sample, with the termination test
    Tick pixel_fill = 0;        // a pixel not cast, interpolated from its square's corners
    Tick refinement_test = 0;   // comparing a square's corner colours
    // What the PPs do on Pixel-planes 5, when one processor does it instead (a uniprocessor machine).
    Tick voxel_classification = 0;
    Tick voxel_shading = 0;
    Tick voxel_region = 0;
    Tick polygon_point_test = 0;  // one sample point against one plane
    Tick voxel_matte = 0;
    // Control work, per operation.
    Tick pyramid_step = 0;      // one visit to a cell of the pyramid of binary volumes
    Tick cache_lookup = 0;
    Tick message_send = 0;      // composing and handing a message to the ring interface
    Tick message_receive = 0;   // taking a message from the ring interface
    Tick receive_per_word = 0;  // copying one received word into the cache
    Tick context_switch = 0;    // saving one ray's state and restoring another's
    Tick pyramid_build_per_cell = 0;

    static const ParamGroup& params();
    static GpCostModel from(const MachineConfig& config);

    // One resampled sample: step, interpolation and compositing.
    Tick per_sample() const { return sample_step + interpolation + compositing; }
};

}  // namespace pp5
