#pragma once
// What the loader tests share: a directory of each test's own, writing the formats' bytes
// (tests/support/volume_files.h) to files plain or gzipped, sample patterns, and the InputError a load throws.

#include "scene/volume/volume.h"
#include "sim/core/input_error.h"
#include "tests/support/input_errors.h"
#include "tests/support/temp_dir.h"
#include "tests/support/volume_files.h"

#include <gtest/gtest.h>
#include <zlib.h>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace pp5::test {

inline void write_file(const std::filesystem::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    ASSERT_TRUE(out.good()) << path;
}

inline void write_gz(const std::filesystem::path& path, const Bytes& bytes) {
    gzFile gz = gzopen(path.c_str(), "wb");
    ASSERT_NE(gz, nullptr) << path;
    ASSERT_EQ(gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size())), static_cast<int>(bytes.size()));
    ASSERT_EQ(gzclose(gz), Z_OK);
}

// A deterministic pattern with distinct values on every axis, to catch transposed index orders.
inline std::vector<float> pattern(glm::ivec3 dims, const std::function<float(int, int, int)>& f) {
    std::vector<float> values;
    for (int z = 0; z < dims.z; ++z) {
        for (int y = 0; y < dims.y; ++y) {
            for (int x = 0; x < dims.x; ++x) values.push_back(f(x, y, z));
        }
    }
    return values;
}

template <class T>
std::vector<T> cast_all(const std::vector<float>& values) {
    std::vector<T> out;
    for (const float v : values) out.push_back(static_cast<T>(v));
    return out;
}

inline std::vector<float> samples_of(const Volume& v) { return {v.samples().begin(), v.samples().end()}; }

}  // namespace pp5::test
