#pragma once
// The frame buffer: receives finished pixels over the ring and scans them out.

#include "sim/core/component.h"
#include "sim/core/config.h"

namespace pp5 {

class FrameBuffer : public Component {
public:
    static const ParamGroup& params();
    explicit FrameBuffer(const MachineConfig& config);

    int width() const { return width_; }
    int height() const { return height_; }
    int bits_per_pixel() const { return bits_per_pixel_; }

    Counter& pixels_written;

private:
    int width_;
    int height_;
    int bits_per_pixel_;
};

// The host workstation: a station on the ring that loads volumes and issues commands.
class Host : public Component {
public:
    Host() : Component("host", nullptr) {}
};

}  // namespace pp5
