#include "scene/volume/volume_info.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace pp5 {

namespace {

std::string group_digits(std::size_t n) {
    const std::string digits = std::to_string(n);
    std::string grouped;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) grouped += ',';
        grouped += digits[i];
    }
    return grouped;
}

std::string human_bytes(std::size_t bytes) {
    const auto b = static_cast<double>(bytes);
    if (b >= 1024.0 * 1024.0 * 1024.0) return fmt::format("{:.1f} GiB", b / (1024.0 * 1024.0 * 1024.0));
    if (b >= 1024.0 * 1024.0) return fmt::format("{:.1f} MiB", b / (1024.0 * 1024.0));
    if (b >= 1024.0) return fmt::format("{:.1f} KiB", b / 1024.0);
    return fmt::format("{} bytes", bytes);
}

struct Summary {
    double mean = 0.0;
    double std_dev = 0.0;
    std::size_t zeros = 0;
    std::array<float, 3> percentiles{};  // 50, 90, 99
};

Summary summarize(std::span<const float> samples) {
    Summary s;
    double sum = 0.0;
    double sum_squares = 0.0;
    for (const float v : samples) {
        sum += static_cast<double>(v);
        sum_squares += static_cast<double>(v) * static_cast<double>(v);
        if (v == 0.0f) ++s.zeros;
    }
    const auto n = static_cast<double>(samples.size());
    s.mean = sum / n;
    s.std_dev = std::sqrt(std::max(0.0, sum_squares / n - s.mean * s.mean));
    // Exact order statistics on a copy: a one-off cost next to loading the file.
    std::vector<float> sorted(samples.begin(), samples.end());
    const std::array<double, 3> at{0.50, 0.90, 0.99};
    for (std::size_t i = 0; i < at.size(); ++i) {
        const auto k = static_cast<std::size_t>(at[i] * (n - 1.0));
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
        s.percentiles[i] = sorted[k];
    }
    return s;
}

}  // namespace

std::string describe_volume(const Volume& volume) {
    const std::string name = volume.name().empty() ? "(unnamed)" : volume.name();
    if (volume.voxel_count() == 0) return fmt::format("name:        {}\ndims:        empty volume\n", name);
    const glm::ivec3 d = volume.dims();
    const glm::vec3 s = volume.spacing();
    const glm::vec3 e = volume.physical_extent();
    const std::size_t n = volume.voxel_count();
    const Summary summary = summarize(volume.samples());

    std::string text;
    text += fmt::format("name:        {}\n", name);
    text += fmt::format("dims:        {} x {} x {} ({} voxels)\n", d.x, d.y, d.z, group_digits(n));
    text += fmt::format("spacing:     {:g} x {:g} x {:g} mm\n", s.x, s.y, s.z);
    text += fmt::format("extent:      {:g} x {:g} x {:g} mm\n", e.x, e.y, e.z);
    text += fmt::format("source type: {} ({} as stored, {} as float samples)\n", to_string(volume.source_type()),
                        human_bytes(n * scalar_size_bytes(volume.source_type())), human_bytes(n * sizeof(float)));
    text += fmt::format("values:      {:g} .. {:g}, mean {:.4g}, std dev {:.4g}\n", volume.min_value(),
                        volume.max_value(), summary.mean, summary.std_dev);
    text += fmt::format("zero voxels: {:.1f}% ({} non-zero)\n",
                        100.0 * static_cast<double>(summary.zeros) / static_cast<double>(n),
                        group_digits(n - summary.zeros));
    text += fmt::format("percentiles: 50% {:g}, 90% {:g}, 99% {:g}\n", summary.percentiles[0], summary.percentiles[1],
                        summary.percentiles[2]);
    return text;
}

}  // namespace pp5
