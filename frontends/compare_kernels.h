#pragma once
// Every kernel on one scenario and one machine, side by side: the same view, transfer function and
// lights rendered by each algorithm that runs on the machine, with its pictures, its distance from the
// oracle, its simulated time and where the time went, what it keeps in the renderers' backing store,
// what it sends over the ring, and, for a kernel that cannot render the scenario, why not.
//
// A kernel that implements the other order of resampling (PERM classifies and shades each sample;
// the others shade voxels and interpolate) renders with image.resampling set to its own order, and the
// report says so: the order is the algorithm, not a setting of the view.

#include "scene/render/image.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pp5 {

struct KernelComparisonRow {
    std::string kernel;
    std::string description;
    std::string refusal;                // why it cannot render the scenario; empty when it rendered
    std::string adaptation;             // what was changed for it (its resampling order); empty when nothing
    std::vector<double> frame_seconds;  // simulated, per frame
    std::optional<double> psnr_db;      // the last frame against the oracle
    std::vector<std::pair<std::string, double>> phases;  // the last frame's phases, simulated seconds
    double gp_utilisation = 0, renderer_utilisation = 0, ring_utilisation = 0;  // the last frame
    double ring_bytes = 0;                                                      // over every frame
    double ring_messages = 0;
    double backing_store_bits_per_pp = 0;  // the busiest renderer's, holding placed data
    double host_seconds = 0;
    Image picture;  // the last frame

    bool rendered() const { return refusal.empty(); }
    double mean_frame_seconds() const;
};

struct KernelComparison {
    std::string scenario;
    std::string machine;
    std::size_t frames = 0;
    std::vector<KernelComparisonRow> rows;  // in the registry's order
};

struct CompareKernelsOptions {
    bool compare_with_reference = true;
};

// Renders every frame of `scenario` with each kernel that runs on the machine. A kernel's InputError
// (it cannot render this scenario, or the machine cannot hold what it needs) becomes its row's
// refusal; nothing else is caught.
KernelComparison compare_kernels(const Scenario& scenario, const MachineConfig& config,
                                 const CompareKernelsOptions& options = {});

nlohmann::json to_json(const KernelComparison& comparison);
// The report as a Markdown table and a paragraph per kernel, naming each kernel's picture as
// `<kernel>.png` and the row of them as `side_by_side.png`.
std::string to_markdown(const KernelComparison& comparison);
// The kernels' last pictures in a row, in the rows' order, with a gap between them.
Image side_by_side(const KernelComparison& comparison);

}  // namespace pp5
