#pragma once
// What `pp5sim serve` shows, apart from HTTP: one scenario rendered on one machine, changed a step at
// a time (orbit the eye, move the light, move, resize or rescale the volume of interest, choose another
// kernel), each change becoming the next frame of a running session, so that only what the change
// invalidates is recomputed, as in Levoy's animation cases. Every change is checked field by field
// before anything is rendered; a bad one is an InputError naming the field, and leaves the view as it was.

#include "frontends/render_session.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

class InteractiveView {
public:
    // Renders the scenario's first frame (InputError when the scenario or the machine cannot run).
    InteractiveView(Scenario scenario, MachineConfig config);

    // Applies `change` (docs/serve.md: camera, light, region, kernel, machine) and renders the resulting
    // frame if anything changed; a change to the machine's timing alone re-times the last frame instead. Throws
    // InputError("request", field, reason) for a bad change, before anything changes.
    void apply(const nlohmann::json& change);

    // The view as the page shows it: the settings, the last frame's simulated times and rates, what it
    // recomputed, each kind of component's utilisation, and the image's version.
    nlohmann::json state() const;
    // The last frame's picture as PNG bytes.
    const std::string& frame_png() const { return frame_png_; }
    // The last frame's refinement passes (none for a kernel without them), and pass p as PNG bytes
    // (encoded when asked for: most changes never show them).
    std::size_t pass_count() const { return passes_.size(); }
    std::string pass_png(std::size_t pass) const { return encode_png(passes_.at(pass)); }
    std::size_t version() const { return version_; }
    // Where the last frame's time went: its phases, the times its passes reached the frame buffer, and
    // a lane of busy time per GP, renderer and ring channel of the machine that timed it, in `bins`
    // slices of the frame (docs/serve.md).
    nlohmann::json timeline(int bins = 480) const;
    // The last frame's screen tiles tinted by the GP that cast each, as PNG bytes; nullopt when its
    // kernel does not cast tiles on GPs.
    std::optional<std::string> tile_map_png() const;
    // How far the last frame's picture is from the reference renderer's (a frame record's `fidelity`:
    // against, psnr_db, rms_error, max_error; null for a kernel not on the machine), with the view's
    // version. Rendered when first asked for after each new picture, not with the frame, so that the
    // frame is shown without waiting for its oracle.
    nlohmann::json reference_fidelity();
    // Renders the view as it stands (its camera, light and region, on the machine frames are timed on)
    // with every kernel that runs on the machine, as `pp5sim compare-kernels` does for one frame: its
    // report (docs/serve.md). Each kernel's picture stays for comparison_png until the next comparison.
    nlohmann::json compare_kernels();
    std::optional<std::string> comparison_png(const std::string& kernel) const;

private:
    // A session on the scenario and machine that keeps this view's trace and defers the reference.
    std::unique_ptr<RenderSession> start_session(const Scenario& scenario, const MachineConfig& config);
    void render(FrameSpec frame);
    // A change to the machine: re-times the last frames when only timing changes, else renders again.
    void change_machine(const nlohmann::json& change);
    // last_ from a frame's record, its kernel's record and its timing on the machine.
    void describe(std::size_t index, const nlohmann::json& record, const KernelFrame& recorded,
                  const FrameTiming& timing);

    Scenario scenario_;
    MachineConfig config_;
    // Keeps the last timed frame's slices for the timeline; made before, and outliving, every session.
    std::unique_ptr<TraceRecorder> trace_;
    std::unique_ptr<RenderSession> session_;
    // The machine frames are timed on: config_ with the timing changes made since the session started
    // (config_ is the machine that records what the kernels compute).
    MachineConfig timing_;
    // The last two recorded frames, which a timing change re-times (the first warms the caches).
    std::vector<std::unique_ptr<KernelFrame>> recent_;
    nlohmann::json last_record_;               // the last frame's record, kept for a re-time
    nlohmann::json machine_change_ = nullptr;  // what the last machine change did
    FrameSpec current_;
    nlohmann::json last_;                   // the last frame's state
    std::vector<std::string> phase_names_;  // every phase the session has timed, in first-seen order
    std::string frame_png_;
    std::vector<Image> passes_;
    Image picture_;            // the last frame, which the tile map is drawn over
    FrameTiming last_timing_;  // the last frame's timing on the timing machine
    std::optional<Image> tile_map_;
    nlohmann::json fidelity_ = nullptr;  // the picture's against the reference, once asked for
    std::vector<std::pair<std::string, Image>> comparison_pictures_;  // by kernel, from the last comparison
    std::size_t version_ = 0;
};

}  // namespace pp5
