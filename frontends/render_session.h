#pragma once
// A scenario's kernel running on one machine, kept alive from frame to frame: what `render` does for
// each frame of a file, and what the Python module and `pp5sim serve` do one change at a time. The
// kernel's run keeps its state (the PPs' shaded volume, the GPs' caches, the pyramid), so a frame that
// only moves the light reshades and casts again, as Levoy's animation cases say, and its statistics
// accumulate as one run's.

#include "frontends/image_io.h"
#include "kernels/api/kernel.h"
#include "scene/reference/reference_renderer.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"
#include "sim/core/trace_recorder.h"
#include "sim/machine/machine.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

// One picture a frame produced, with the file name `render` gives it.
struct FrameImage {
    enum class Kind { Pass, Difference, Frame };
    Kind kind = Kind::Frame;
    std::size_t pass = 0;  // Pass and Difference: which stage
    std::string name;      // "frame_0003_pass_1.png"
    Image image;
};

struct SessionFrame {
    std::size_t index = 0;
    FrameTiming timing;                     // with the components' activity over the frame
    std::vector<FrameImage> images;         // the passes (on the machine), difference images, then the frame
    nlohmann::json record;                  // the frame's record in stats.json
    std::unique_ptr<KernelFrame> recorded;  // the kernel's record (its images moved into `images`)
    // The last image of a kind ("the frame", or pass p); nullptr when there is none.
    const Image* find(FrameImage::Kind kind, std::size_t pass = 0) const;
};

// The bytes of the pictures a session holds at once for one frame of `scenario` on `kernel`: the
// kernel's pass pictures and, on the machine, the frame's copy and, when comparing with the reference,
// the reference picture and a difference image for each comparison (RGBA float, 16 bytes a pixel) and
// the two RGB float buffers a comparison makes.
// Checked against this computer's memory before the volume is read.
double picture_bytes_per_frame(const Kernel& kernel, const Scenario& scenario, const MachineConfig& config,
                               bool compare_with_reference = true);

class RenderSession {
public:
    // Checks the scenario against its kernel and the machine, loads the volume and starts the kernel
    // (InputError when something cannot fit, before any frame). Frames are named with `extension`.
    // Without `compare_with_reference` no host reference picture is made, so frames carry no PSNR; the
    // reference needs about 55 bytes a voxel of its own (0.94 GB at 256^3), more than the simulated
    // machine, which matters for big volumes.
    RenderSession(const Scenario& scenario, const MachineConfig& config, TraceRecorder* trace = nullptr,
                  std::string extension = "png", bool compare_with_reference = true);

    // Computes and times the next frame. `frame` says what changed since the frame before (the first
    // frame of a session changes everything, whatever it says).
    SessionFrame render(FrameSpec frame);

    // From now on frames are not compared with the reference as they are rendered (their records
    // have no fidelity): compare_with_reference does it when asked, so that an interactive view shows
    // a frame without waiting for its oracle. Without a reference (compare_with_reference false at
    // construction) there is nothing to defer.
    void defer_reference_comparison() { defer_reference_ = true; }
    // The reference picture of `frame` (the last one rendered) against `picture`, as a frame record's
    // `fidelity` (against, psnr_db, rms_error, max_error); null without a reference.
    nlohmann::json compare_with_reference(const FrameSpec& frame, const Image& picture);

    // stats.json's document for the frames rendered so far (`frames`: their records, in order).
    nlohmann::json stats(const nlohmann::json& frames, double host_seconds) const;
    // A few lines for a terminal: the machine, the dataset, then one per frame record.
    std::vector<std::string> summary_lines(const nlohmann::json& frames) const;

    // From now on, times frames on `timing`, a machine that differs from the session's only in timing
    // parameters (InputError naming the first key that does not), with caches starting cold, and first
    // times `replay` on it (the frames before, in order) so that what follows finds the caches as that
    // machine would have left them. Returns the last of replay's timings. The recording
    // machine stays as it was: what the kernels computed does not depend on timing. The session's trace,
    // if it has one, records the frames timed on `timing` from then on.
    FrameTiming retime_on(const MachineConfig& timing, const std::vector<const FrameWork*>& replay);
    // The configuration frames are timed with (the session's own until retime_on).
    const MachineConfig& timing_config() const { return timing_config_ ? *timing_config_ : config_; }
    // The machine frames are timed on (the session's own until retime_on).
    const Machine& timing_machine() const { return timing_machine_ ? *timing_machine_ : machine_; }

    const Scenario& scenario() const { return scenario_; }
    const Kernel& kernel() const { return kernel_; }
    const MachineConfig& config() const { return config_; }
    const Machine& machine() const { return machine_; }
    const Volume& volume() const { return volume_; }
    std::size_t frames_rendered() const { return frames_rendered_; }

private:
    std::string reference_includes(const FrameSpec& frame) const;
    // The reference picture of `frame`, after taking in what the frames since it last rendered changed.
    Image render_reference(const FrameSpec& frame, RenderStats* counts);
    Volume load_checked_volume(TraceRecorder* trace);

    Scenario scenario_;
    MachineConfig config_;
    const Kernel& kernel_;
    std::string extension_;
    bool compare_with_reference_;
    Machine machine_;
    TraceRecorder* trace_;  // the user's, or none; the slices it keeps are the last timed frame's
    Volume volume_;
    std::unique_ptr<KernelRun> run_;
    // After retime_on: the machine frames are timed on (the recording machine_ keeps the kernel's state).
    std::optional<MachineConfig> timing_config_;
    std::unique_ptr<Machine> timing_machine_;
    std::optional<ReferenceRenderer> reference_;
    bool defer_reference_ = false;
    // What the frames since the reference last rendered changed, which it must take in before it
    // renders again (a deferred comparison may skip frames).
    bool reference_classification_stale_ = false;
    bool reference_lighting_stale_ = false;
    std::size_t frames_rendered_ = 0;
};

}  // namespace pp5
