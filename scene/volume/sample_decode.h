#pragma once
// Turns the sample bytes of a volume file into the float samples a Volume holds. Internal to
// scene/volume: every loader ends here, so byte order, scaling and the rejection of NaN and
// infinite samples are done once.

#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <bit>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace pp5::volume_detail {

struct SampleEncoding {
    ScalarType type = ScalarType::UInt8;
    std::endian order = std::endian::little;
    // value = slope * stored + intercept; (1, 0) means the stored values as they are.
    double slope = 1.0;
    double intercept = 0.0;
};

// bytes.size() must be voxel_count(dims) * scalar_size_bytes(type). Throws InputError(file,
// "voxel data", ...) naming the first voxel that is NaN, infinite or beyond float range.
std::vector<float> decode_samples(std::span<const std::byte> bytes, const SampleEncoding& encoding, glm::ivec3 dims,
                                  const std::string& file);

}  // namespace pp5::volume_detail
