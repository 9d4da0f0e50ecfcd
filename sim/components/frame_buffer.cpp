#include "sim/components/frame_buffer.h"

namespace pp5 {

const ParamGroup& FrameBuffer::params() {
    static const ParamGroup group = [] {
        ParamGroup g("frame_buffer", "The colour frame buffer");
        g.integer("width", 512, "pixels", 1, 8192, "Frame buffer width", Provenance::Paper,
                  "Levoy 1989: a 512 x 512 pixel color frame buffer")
            .integer("height", 512, "pixels", 1, 8192, "Frame buffer height", Provenance::Paper,
                     "Levoy 1989: a 512 x 512 pixel color frame buffer")
            .integer("bits_per_pixel", 24, "bits", 1, 128, "Colour depth of a stored pixel", Provenance::Default,
                     "not stated for Levoy's configuration; 8 bits per RGB channel")
            .plausible(24, 32,
                       "a colour frame buffer of the time: 8 bits a channel, perhaps with a padding or alpha byte")
            .timing_only();
        return g;
    }();
    return group;
}

FrameBuffer::FrameBuffer(const MachineConfig& config)
    : Component("frame_buffer", nullptr),
      pixels_written(stats().counter("pixels_written", "count", "Pixels received from the GPs")),
      width_(static_cast<int>(config.integer("frame_buffer.width"))),
      height_(static_cast<int>(config.integer("frame_buffer.height"))),
      bits_per_pixel_(static_cast<int>(config.integer("frame_buffer.bits_per_pixel"))) {}

}  // namespace pp5
