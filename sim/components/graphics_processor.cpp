#include "sim/components/graphics_processor.h"

namespace pp5 {

const ParamGroup& GraphicsProcessor::params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp", "Graphics processors: Intel i860 nodes that trace rays");
        g.integer("count", 32, "count", 1, 1024, "Number of graphics processors", Provenance::Paper,
                  "Levoy 1989, Implementation on Pixel-planes 5: 32 GPs")
            .real("clock_mhz", 40.0, "MHz", 1, 1000, "i860 core clock", Provenance::Hardware,
                  "Fuchs et al. 1989: Intel i860 at 40 MHz")
            .real("sustained_mflops", 20.0, "MFLOPS", 0.1, 1e5, "Floating-point rate a GP sustains on ray tracing",
                  Provenance::Paper, "Levoy 1989: 20-MFLOP graphics processors (i860 peak is 80)")
            .integer("cache_bits", 16 * 1024 * 1024, "bits", 1024, 1LL << 40,
                     "Voxel cache capacity per GP (16 Mbit = 2 MiB)", Provenance::Paper,
                     "Levoy 1989: voxels retained in a 16Mb local cache")
            .integer("memory_bytes", 8 * 1024 * 1024, "bytes", 1024, 1LL << 40, "Memory per GP board",
                     Provenance::Default, "machine.md: about 8 MB per GP board, not confirmed")
            .integer("ray_contexts", 8, "count", 1, 4096,
                     "Rays a GP keeps in flight, switching between them while voxel requests are outstanding",
                     Provenance::Default, "Levoy 1989 says 'several rays' without a number");
        return g;
    }();
    return group;
}

GraphicsProcessor::GraphicsProcessor(std::size_t index, const MachineConfig& config)
    : Component(indexed("gp", index), nullptr),
      rays(stats().counter("rays", "count", "Rays traced to completion")),
      samples(stats().counter("samples", "count", "Resampling points interpolated and composited")),
      busy_ps(stats().counter("busy_time", "ps", "Simulated time spent computing")),
      wait_ps(stats().counter("wait_time", "ps", "Simulated time with every ray context waiting for voxels")),
      index_(index),
      clock_(ClockDomain::from_megahertz(name() + ".clock", config.real("gp.clock_mhz"))),
      cache_bits_(static_cast<std::uint64_t>(config.integer("gp.cache_bits"))),
      ray_contexts_(static_cast<int>(config.integer("gp.ray_contexts"))) {}

}  // namespace pp5
