// `pp5sim volume-info FILE`: what a volume file holds, or why it cannot be read.

#include "frontends/cli/commands.h"
#include "scene/volume/datasets.h"
#include "scene/volume/volume_info.h"
#include "scene/volume/volume_io.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <filesystem>

namespace pp5::cli {
namespace {

struct VolumeInfoOptions {
    std::string file;
    std::vector<int> raw_dims;
    std::string raw_type;
    bool big_endian = false;
    std::size_t header_bytes = 0;
    std::vector<float> spacing;
};

int run_volume_info(const VolumeInfoOptions& o) {
    Volume volume;
    const bool raw = !o.raw_dims.empty() || !o.raw_type.empty();
    if (raw) {
        if (o.raw_dims.size() != 3 || o.raw_type.empty())
            throw InputError(o.file, "--dims/--type", "a raw file needs both --dims X Y Z and --type");
        const auto type = parse_scalar_type(o.raw_type);
        if (!type) throw InputError(o.file, "--type", "unknown scalar type \"" + o.raw_type + "\"");
        RawLayout layout{
            {o.raw_dims[0], o.raw_dims[1], o.raw_dims[2]}, *type, o.big_endian, o.header_bytes, glm::vec3(1.0f)};
        if (o.spacing.size() == 3) layout.spacing = {o.spacing[0], o.spacing[1], o.spacing[2]};
        volume = load_raw(o.file, layout);
    } else if (std::error_code unreadable;
               !std::filesystem::exists(o.file, unreadable) && find_packaged_dataset(o.file)) {
        volume = load_packaged_dataset(o.file);
    } else {
        volume = load_volume(o.file);
    }
    fmt::print("{}", describe_volume(volume));
    return 0;
}

}  // namespace

void add_volume_info_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<VolumeInfoOptions>();
    CLI::App* cmd = app.add_subcommand(
        "volume-info",
        "Describe a volume: a NIfTI-1 (.nii, .nii.gz), UNC .den or raw file, or a packaged dataset name (ch2)");
    cmd->add_option("file", o->file, "Volume file, or the name of a Debian-packaged dataset")->required();
    cmd->add_option("--dims", o->raw_dims, "Raw file: dimensions X Y Z")->expected(3);
    cmd->add_option("--type", o->raw_type, "Raw file: scalar type (uint8, int16, uint16, float32, ...)");
    cmd->add_flag("--big-endian", o->big_endian, "Raw file: samples are big-endian");
    cmd->add_option("--header-bytes", o->header_bytes, "Raw file: bytes to skip before the samples")
        ->check(whole_number());
    cmd->add_option("--spacing", o->spacing, "Raw file: voxel spacing X Y Z in mm")->expected(3);
    cmd->callback([o, &run] { run = [o] { return run_volume_info(*o); }; });
}

}  // namespace pp5::cli
