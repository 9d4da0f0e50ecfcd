#pragma once
// What `pp5sim serve` shows, apart from HTTP: one scenario rendered on one machine, changed a step at
// a time (orbit the eye, move the light, move, resize or rescale the volume of interest, choose another
// kernel), each change becoming the next frame of a running session, so that only what the change
// invalidates is recomputed, as in Levoy's animation cases. Every change is checked field by field
// before anything is rendered; a bad one is an InputError naming the field, and leaves the view as it was.

#include "frontends/render_session.h"
#include "kernels/scenario/scenario.h"
#include "sim/core/config.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace pp5 {

class InteractiveView {
public:
    // Renders the scenario's first frame (InputError when the scenario or the machine cannot run).
    InteractiveView(Scenario scenario, MachineConfig config);

    // Applies `change` (docs/serve.md: camera, light, region, kernel) and renders the resulting frame
    // if anything changed. Throws InputError("request", field, reason) for a bad change,
    // before anything changes.
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

private:
    void render(FrameSpec frame);

    Scenario scenario_;
    MachineConfig config_;
    std::unique_ptr<RenderSession> session_;
    FrameSpec current_;
    nlohmann::json last_;  // the last frame's state
    std::vector<std::string> phase_names_;  // every phase the session has timed, in first-seen order
    std::string frame_png_;
    std::vector<Image> passes_;
    std::size_t version_ = 0;
};

}  // namespace pp5
