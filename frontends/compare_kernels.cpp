#include "frontends/compare_kernels.h"

#include "frontends/render_session.h"
#include "kernels/registry/registry.h"
#include "sim/core/input_error.h"
#include "sim/core/time.h"
#include "sim/machine/machine.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <numeric>

namespace pp5 {

namespace {

const char* order_name(ResamplingOrder order) {
    return order == ResamplingOrder::InterpolateThenShade ? "interpolate-then-shade" : "shade-then-interpolate";
}

// The scenario as `kernel` renders it: the same, or with the other resampling order when that is the
// only thing it refuses. Throws the kernel's InputError otherwise.
Scenario scenario_for(const Kernel& kernel, const Scenario& scenario, std::string& adaptation) {
    Scenario own = scenario;
    own.kernel = kernel.name();
    try {
        check_scenario(kernel, own);
        return own;
    } catch (const InputError& e) {
        if (e.field() != "image.resampling") throw;
        own.image.resampling = own.image.resampling == ResamplingOrder::ShadeThenInterpolate
                                   ? ResamplingOrder::InterpolateThenShade
                                   : ResamplingOrder::ShadeThenInterpolate;
        check_scenario(kernel, own);
        adaptation = fmt::format("renders with image.resampling = \"{}\", the order it implements",
                                 order_name(own.image.resampling));
        return own;
    }
}

// A statistic's value in Machine::statistics(): a number, or the sum of a breakdown's numbers.
double statistic(const nlohmann::json& components, const std::string& component, const std::string& name) {
    if (!components.contains(component) || !components[component].contains(name)) return 0.0;
    const nlohmann::json& value = components[component][name]["value"];
    if (value.is_number()) return value.get<double>();
    double sum = 0.0;
    for (const auto& [key, part] : value.items())
        if (part.is_number()) sum += part.get<double>();
    return sum;
}

void render_row(const Kernel& kernel, const Scenario& scenario, const MachineConfig& config,
                const CompareKernelsOptions& options, KernelComparisonRow& row) {
    const auto started = std::chrono::steady_clock::now();
    const Scenario own = scenario_for(kernel, scenario, row.adaptation);
    RenderSession session(own, config, nullptr, "png", options.compare_with_reference);
    for (const FrameSpec& frame : own.frames) {
        const SessionFrame rendered = session.render(frame);
        row.frame_seconds.push_back(ticks_to_seconds(rendered.timing.duration_ps()));
        row.phases.clear();
        for (const PhaseTiming& phase : rendered.timing.phases)
            row.phases.emplace_back(phase.name, ticks_to_seconds(phase.duration_ps()));
        row.gp_utilisation = rendered.timing.activity.gps;
        row.renderer_utilisation = rendered.timing.activity.renderers;
        row.ring_utilisation = rendered.timing.activity.ring;
        row.psnr_db.reset();
        if (rendered.record.contains("fidelity") && rendered.record["fidelity"]["psnr_db"].is_number())
            row.psnr_db = rendered.record["fidelity"]["psnr_db"].get<double>();
        if (const Image* picture = rendered.find(FrameImage::Kind::Frame)) row.picture = *picture;
    }
    const nlohmann::json components = session.machine().statistics();
    row.ring_bytes = statistic(components, "ring", "bytes");
    row.ring_messages = statistic(components, "ring", "messages");
    for (std::size_t r = 0; r < session.machine().renderers().size(); ++r)
        row.backing_store_bits_per_pp =
            std::max(row.backing_store_bits_per_pp,
                     statistic(components, fmt::format("renderer[{}]", r), "backing_store_bits_used"));
    row.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

std::string number(double value, const char* format = "{:.4g}") { return fmt::format(fmt::runtime(format), value); }

}  // namespace

double KernelComparisonRow::mean_frame_seconds() const {
    return frame_seconds.empty() ? 0.0
                                 : std::accumulate(frame_seconds.begin(), frame_seconds.end(), 0.0) /
                                       static_cast<double>(frame_seconds.size());
}

KernelComparison compare_kernels(const Scenario& scenario, const MachineConfig& config,
                                 const CompareKernelsOptions& options) {
    KernelComparison comparison{scenario.name, config.machine_name(), scenario.frames.size(), {}};
    for (const Kernel* kernel : kernels()) {
        if (!kernel->runs_on_machine()) continue;  // the host reference is the oracle every row is measured against
        KernelComparisonRow row;
        row.kernel = kernel->name();
        row.description = kernel->description();
        try {
            render_row(*kernel, scenario, config, options, row);
        } catch (const InputError& e) {
            KernelComparisonRow refused;
            refused.kernel = kernel->name();
            refused.description = kernel->description();
            refused.refusal = e.what();
            row = std::move(refused);
        }
        comparison.rows.push_back(std::move(row));
    }
    return comparison;
}

nlohmann::json to_json(const KernelComparison& comparison) {
    nlohmann::json rows = nlohmann::json::array();
    for (const KernelComparisonRow& r : comparison.rows) {
        nlohmann::json row = {{"kernel", r.kernel}, {"description", r.description}};
        if (!r.rendered()) {
            row["refusal"] = r.refusal;
            rows.push_back(std::move(row));
            continue;
        }
        nlohmann::json phases = nlohmann::json::object();
        for (const auto& [name, seconds] : r.phases) phases[name] = seconds;
        row.update({{"adaptation", r.adaptation},
                    {"frame_seconds", r.frame_seconds},
                    {"mean_frame_seconds", r.mean_frame_seconds()},
                    {"psnr_db", r.psnr_db ? nlohmann::json(*r.psnr_db) : nlohmann::json(nullptr)},
                    {"phases_seconds", phases},
                    {"utilisation",
                     {{"gps", r.gp_utilisation}, {"renderers", r.renderer_utilisation}, {"ring", r.ring_utilisation}}},
                    {"ring_bytes", r.ring_bytes},
                    {"ring_messages", r.ring_messages},
                    {"backing_store_bits_per_pp", r.backing_store_bits_per_pp},
                    {"host_seconds", r.host_seconds},
                    {"picture", r.kernel + ".png"}});
        rows.push_back(std::move(row));
    }
    return {{"scenario", comparison.scenario},
            {"machine", comparison.machine},
            {"frames", comparison.frames},
            {"kernels", rows}};
}

std::string to_markdown(const KernelComparison& comparison) {
    std::string md = fmt::format("# Every kernel on {} ({} frame{}, machine {})\n\n", comparison.scenario,
                                 comparison.frames, comparison.frames == 1 ? "" : "s", comparison.machine);
    md += "The same view, transfer function and lights; `side_by_side.png` shows the last frames in this order.\n\n";
    md +=
        "| kernel | mean frame (ms) | frames/s | PSNR (dB) | GPs busy | renderers busy | ring busy | ring MB | backing "
        "store "
        "(bits/PP) | host (s) |\n";
    md += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const KernelComparisonRow& r : comparison.rows) {
        if (!r.rendered()) {
            md += fmt::format("| {} | refused | | | | | | | | |\n", r.kernel);
            continue;
        }
        const double mean = r.mean_frame_seconds();
        md += fmt::format("| {} | {} | {} | {} | {:.0f}% | {:.0f}% | {:.0f}% | {} | {:.0f} | {:.2f} |\n", r.kernel,
                          number(1e3 * mean), mean > 0 ? number(1.0 / mean, "{:.3g}") : std::string("-"),
                          r.psnr_db ? number(*r.psnr_db, "{:.1f}") : std::string("-"), 100 * r.gp_utilisation,
                          100 * r.renderer_utilisation, 100 * r.ring_utilisation, number(r.ring_bytes / 1e6, "{:.3g}"),
                          r.backing_store_bits_per_pp, r.host_seconds);
    }
    md += "\n";
    for (const KernelComparisonRow& r : comparison.rows) {
        md += fmt::format("## {}\n\n{}\n\n", r.kernel, r.description);
        if (!r.rendered()) {
            md += fmt::format("Cannot render this scenario: {}\n\n", r.refusal);
            continue;
        }
        if (!r.adaptation.empty()) md += "It " + r.adaptation + ".\n\n";
        md += fmt::format("![{}]({}.png)\n\nWhere the last frame's {} ms went:", r.kernel, r.kernel,
                          number(1e3 * r.frame_seconds.back()));
        for (const auto& [name, seconds] : r.phases) md += fmt::format(" {} {} ms;", name, number(1e3 * seconds));
        md.back() = '.';
        md += "\n\n";
    }
    return md;
}

Image side_by_side(const KernelComparison& comparison) {
    constexpr int kGap = 8;
    int width = 0, height = 0;
    for (const KernelComparisonRow& r : comparison.rows) {
        if (!r.rendered()) continue;
        width += (width > 0 ? kGap : 0) + r.picture.width;
        height = std::max(height, r.picture.height);
    }
    Image strip(width, height);
    for (glm::vec4& p : strip.pixels) p = glm::vec4(1.0f);  // white gaps and margins
    int x0 = 0;
    for (const KernelComparisonRow& r : comparison.rows) {
        if (!r.rendered()) continue;
        for (int y = 0; y < r.picture.height; ++y)
            for (int x = 0; x < r.picture.width; ++x) strip.at(x0 + x, y) = r.picture.at(x, y);
        x0 += r.picture.width + kGap;
    }
    return strip;
}

}  // namespace pp5
