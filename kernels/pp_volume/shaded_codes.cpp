#include "kernels/pp_volume/shaded_codes.h"

namespace pp5 {

ShadedVolume ShadedCodes::decoded() const {
    ShadedVolume volume;
    volume.dims = dims;
    volume.spacing = spacing;
    volume.rgba.resize(codes.size());
    for (std::size_t i = 0; i < codes.size(); ++i) volume.rgba[i] = value(i);
    return volume;
}

}  // namespace pp5
