#include "sim/components/renderer.h"

namespace pp5 {

const ParamGroup& Renderer::params() {
    static const ParamGroup group = [] {
        ParamGroup g("renderer", "Renderers: SIMD arrays of bit-serial pixel processors");
        g.integer("count", 16, "count", 1, 1024, "Number of renderers", Provenance::Paper,
                  "Levoy 1989: 1/4 million PPs in 16 renderers")
            .integer("pp_columns", 128, "count", 1, 4096, "Pixel processors per row of the array",
                     Provenance::Hardware, "Fuchs et al. 1989: 128x128 PPs per renderer")
            .integer("pp_rows", 128, "count", 1, 4096, "Pixel processors per column of the array",
                     Provenance::Hardware, "Fuchs et al. 1989: 128x128 PPs per renderer")
            .integer("local_memory_bits", 208, "bits", 8, 1 << 20, "On-chip memory per pixel processor",
                     Provenance::Hardware, "Fuchs et al. 1989: 208 bits per PP")
            .integer("backing_store_bits", 4096, "bits", 0, 1 << 24, "Off-chip backing store per pixel processor",
                     Provenance::Paper, "Levoy 1989 and Fuchs et al. 1989: 4K bits per PP")
            .integer("backing_store_block_bits", 32, "bits", 1, 4096,
                     "Size of one backing-store transfer between local memory and the backing store",
                     Provenance::Hardware, "Fuchs et al. 1989: moved in 32-bit blocks")
            .real("clock_mhz", 40.0, "MHz", 1, 1000, "Pixel-processor clock", Provenance::Hardware,
                  "Fuchs et al. 1989: chips designed for 40 MHz");
        return g;
    }();
    return group;
}

Renderer::Renderer(std::size_t index, const MachineConfig& config)
    : Component(indexed("renderer", index), nullptr),
      busy_ps(stats().counter("busy_time", "ps", "Simulated time the PP array spent executing")),
      voxel_requests(stats().counter("voxel_requests", "count", "Voxel requests answered for the GPs")),
      index_(index),
      clock_(ClockDomain::from_megahertz(name() + ".clock", config.real("renderer.clock_mhz"))),
      columns_(static_cast<std::uint64_t>(config.integer("renderer.pp_columns"))),
      rows_(static_cast<std::uint64_t>(config.integer("renderer.pp_rows"))),
      local_memory_bits_(static_cast<std::uint64_t>(config.integer("renderer.local_memory_bits"))),
      backing_store_bits_(static_cast<std::uint64_t>(config.integer("renderer.backing_store_bits"))) {
    stats().formula("pixel_processors", "count", "Pixel processors in this renderer's array",
                    [this] { return static_cast<double>(pixel_processors()); });
    stats().formula("memory_bits", "bits", "Local memory plus backing store over all of this renderer's PPs",
                    [this] { return static_cast<double>(pixel_processors() * (local_memory_bits_ + backing_store_bits_)); });
}

}  // namespace pp5
