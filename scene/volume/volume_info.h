#pragma once
// A volume described in a few lines for people: what `pp5sim volume-info FILE` prints.

#include "scene/volume/volume.h"

#include <string>

namespace pp5 {

// Name, dims, spacing, physical extent, source type, memory, value range and a histogram summary
// (mean, standard deviation, share of zero voxels, percentiles). Each line ends in '\n'.
std::string describe_volume(const Volume& volume);

}  // namespace pp5
