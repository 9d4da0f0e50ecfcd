#include "sim/components/gp_cost_model.h"

#include "sim/core/calibration.h"

#include <cmath>

namespace pp5 {

const ParamGroup& GpCostModel::params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost", "Graphics-processor (i860) cost of each operation class; none is published");
        const auto flops = [&g](const char* name, double def, const char* doc, const char* count) {
            g.real(name, def, "flops", 0, 1e6, doc, Provenance::Default, count);
        };
        const auto cycles = [&g](const char* name, double def, const char* doc, const char* count) {
            g.real(name, def, "cycles", 0, 1e7, doc, Provenance::Default, count);
        };
        flops("ray_setup_flops", 60, "Set up a ray: origin, direction, entry into and exit from the volume",
              "a pixel's ray (about 15 flops) and a slab test against the box (about 45)");
        flops("sample_step_flops", 6, "Advance a ray to its next sample and find the cell around it",
              "three adds for the position, three conversions for the cell");
        flops("interpolation_flops", 56, "Trilinear interpolation of colour and opacity at a sample",
              "seven linear interpolations (two flops each) in four channels");
        flops("compositing_flops", 10, "Composite one sample front to back and test for termination",
              "(1 - A) alpha, three colour multiply-adds, the opacity update and a compare");
        flops("pixel_fill_flops", 18, "Fill a pixel that was not cast by interpolating its square's corners",
              "bilinear interpolation: three linear interpolations in three channels");
        flops("refinement_test_flops", 24, "Decide whether to subdivide a square from its corner colours",
              "six corner pairs in three channels: a subtract and a compare each is 36; with early exit about 24");
        // Work that Pixel-planes 5 gives its PPs, done by a lone processor (the `uniprocessor` machine kind).
        flops("voxel_classification_flops", 8, "Classify one voxel on a processor without PPs: opacity from value and gradient",
              "a table look-up, the gradient magnitude's scale and a multiply: about 8");
        flops("voxel_shading_flops", 40, "Phong-shade one voxel on a processor without PPs",
              "normalise the gradient (about 12 with a reciprocal square root), the diffuse dot product and "
              "clamp (6), three colour multiply-adds with the ambient term (9), and the opacity-weighted colour (4); "
              "with the look-ups, about 40");
        flops("voxel_region_flops", 12, "Scale one voxel's opacity by the volume-of-interest tool on a processor without PPs",
              "the distance to a box or ellipsoid (about 9) and the scale across the transition (3)");
        flops("polygon_point_test_flops", 2, "Test one subvoxel sample point against one of a polygon's planes (sheet or edge)",
              "the plane's linear function stepped incrementally along a scanline (an add) and a compare");
        flops("voxel_matte_flops", 12, "Matte a scan-converted polygon over one voxel",
              "coverage times opacity, the opacity update and three colour blends");
        cycles("pyramid_step_cycles", 40, "Visit one cell of the pyramid of binary volumes",
               "a bit test, a level change or a box exit: about 20 flops of bookkeeping at 2 cycles each");
        cycles("cache_lookup_cycles", 10, "Look a block up in the voxel cache", "a hash, a set index and up to 8 tag compares");
        cycles("message_send_cycles", 50, "Compose a message and hand it to the ring interface",
               "a header and a few stores to the interface's registers");
        cycles("message_receive_cycles", 50, "Take a message from the ring interface", "the same, in the other direction");
        cycles("receive_cycles_per_word", 1, "Copy one received word into the cache", "a load and a store, pipelined");
        cycles("context_switch_cycles", 32, "Save a waiting ray's state and restore a ready one's",
               "about 16 registers of ray state out and in");
        cycles("pyramid_build_cycles_per_cell", 2, "Build one cell of the pyramid of binary volumes from the bits below it",
               "an OR of eight bits, done a word of cells at a time");
        return g;
    }();
    return group;
}

GpCostModel GpCostModel::from(const MachineConfig& config) {
    const CalibrationScales scales = CalibrationScales::from(config);
    const double flop_ps = scales.gp_flops * 1e12 / (config.real("gp.sustained_mflops") * 1e6);
    const double cycle_ps = scales.gp_cycles * 1e12 / (config.real("gp.clock_mhz") * 1e6);
    const auto flops = [&](const char* name) { return static_cast<Tick>(std::llround(config.real(std::string("gp_cost.") + name) * flop_ps)); };
    const auto cycles = [&](const char* name) { return static_cast<Tick>(std::llround(config.real(std::string("gp_cost.") + name) * cycle_ps)); };
    GpCostModel m;
    m.ray_setup = flops("ray_setup_flops");
    m.sample_step = flops("sample_step_flops");
    m.interpolation = flops("interpolation_flops");
    m.compositing = flops("compositing_flops");
    m.pixel_fill = flops("pixel_fill_flops");
    m.refinement_test = flops("refinement_test_flops");
    m.voxel_classification = flops("voxel_classification_flops");
    m.voxel_shading = flops("voxel_shading_flops");
    m.voxel_region = flops("voxel_region_flops");
    m.polygon_point_test = flops("polygon_point_test_flops");
    m.voxel_matte = flops("voxel_matte_flops");
    m.pyramid_step = cycles("pyramid_step_cycles");
    m.cache_lookup = cycles("cache_lookup_cycles");
    m.message_send = cycles("message_send_cycles");
    m.message_receive = cycles("message_receive_cycles");
    m.receive_per_word = cycles("receive_cycles_per_word");
    m.context_switch = cycles("context_switch_cycles");
    m.pyramid_build_per_cell = cycles("pyramid_build_cycles_per_cell");
    return m;
}

}  // namespace pp5
