#pragma once
// Writers for the volume file formats, so the loader tests make their own inputs: the bytes of each
// file are spelled out here from the format's definition, independently of the loaders.

#include "kernels/volume/volume.h"
#include "sim/core/input_error.h"

#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <zlib.h>

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
#include <unistd.h>
#include <vector>

namespace pp5::test {

using Bytes = std::vector<std::byte>;

// A directory of its own for each test, removed afterwards; named by test and process so that
// tests run in parallel (ctest -j) never share files.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string leaf = std::string("pp5_volume_") + info->test_suite_name() + "_" + info->name() + "_" +
                           std::to_string(::getpid());
        for (char& c : leaf) {
            if (c == '/') c = '_';
        }
        path_ = std::filesystem::temp_directory_path() / leaf;
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

template <class T>
void append(Bytes& out, T value, std::endian order = std::endian::little) {
    auto raw = std::bit_cast<std::array<std::byte, sizeof(T)>>(value);
    if (order != std::endian::native) std::reverse(raw.begin(), raw.end());
    out.insert(out.end(), raw.begin(), raw.end());
}

template <class T>
Bytes sample_bytes(const std::vector<T>& values, std::endian order = std::endian::little) {
    Bytes out;
    for (const T v : values) append(out, v, order);
    return out;
}

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

// The fields of a NIfTI-1 header the loader reads, with the defaults of a valid 3D uint8 file.
struct NiftiSpec {
    std::int32_t sizeof_hdr = 348;
    std::array<std::int16_t, 8> dim{3, 1, 1, 1, 1, 1, 1, 1};
    std::int16_t datatype = 2;
    std::int16_t bitpix = 8;
    std::array<float, 8> pixdim{1, 1, 1, 1, 1, 1, 1, 1};
    float vox_offset = 352;
    float scl_slope = 0;
    float scl_inter = 0;
    std::uint8_t xyzt_units = 2;  // mm
    std::array<char, 4> magic{'n', '+', '1', '\0'};
    std::endian order = std::endian::little;

    void set_dims(int x, int y, int z) {
        dim[1] = static_cast<std::int16_t>(x);
        dim[2] = static_cast<std::int16_t>(y);
        dim[3] = static_cast<std::int16_t>(z);
    }
};

// Header at the offsets of nifti1.h's struct nifti_1_header, zero padding up to vox_offset, samples.
inline Bytes nifti_bytes(const NiftiSpec& s, const Bytes& samples) {
    Bytes out;
    append(out, s.sizeof_hdr, s.order);
    out.resize(40);
    for (const auto d : s.dim) append(out, d, s.order);  // 40
    out.resize(70);
    append(out, s.datatype, s.order);  // 70
    append(out, s.bitpix, s.order);    // 72
    out.resize(76);
    for (const auto p : s.pixdim) append(out, p, s.order);  // 76
    append(out, s.vox_offset, s.order);                     // 108
    append(out, s.scl_slope, s.order);                      // 112
    append(out, s.scl_inter, s.order);                      // 116
    out.resize(123);
    out.push_back(static_cast<std::byte>(s.xyzt_units));  // 123
    out.resize(344);
    for (const char c : s.magic) out.push_back(static_cast<std::byte>(c));  // 344
    EXPECT_EQ(out.size(), 348u);
    if (s.vox_offset >= 348) out.resize(static_cast<std::size_t>(s.vox_offset));
    out.insert(out.end(), samples.begin(), samples.end());
    return out;
}

// A .den file laid out as denfile.c's write_den does, in the given byte order.
inline Bytes den_bytes(glm::ivec3 dims, const Bytes& samples, std::endian order = std::endian::little,
                       std::int16_t version = 1) {
    Bytes out;
    append(out, version, order);
    const auto d = [](int v) { return static_cast<std::int16_t>(v); };
    for (int group = 0; group < 3; ++group) {  // orig, extr, map
        for (int i = 0; i < 3; ++i) append(out, d(0), order);                // min
        for (int i = 0; i < 3; ++i) append(out, d(dims[i] - 1), order);      // max
        for (int i = 0; i < 3; ++i) append(out, d(dims[i]), order);          // len
    }
    append(out, d(0), order);  // map_warps
    append(out, static_cast<std::int32_t>(dims.x * dims.y * dims.z), order);
    EXPECT_EQ(out.size(), 62u);
    out.insert(out.end(), samples.begin(), samples.end());
    return out;
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

// Runs `load` and returns the InputError it throws; fails the test if it throws nothing.
template <class Fn>
InputError input_error_from(Fn&& load) {
    try {
        load();
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "expected an InputError";
    return InputError("", "", "no error");
}

}  // namespace pp5::test
