#pragma once
// The renderers' pixel processors as a voxel store, Levoy's first stage and shared by every kernel that
// keeps the volume in the PPs: they hold the value and gradient of every voxel (placed by
// voxel_placement.h) and classify and shade all of it in parallel, leaving a colour and an opacity in
// every voxel slot for the GPs to fetch (ray casting) or stream out (splatting).
//
// PpShading places and loads the volume once, then for each frame reruns only what changed: the
// classification program when the classification changed, the shading program when the colours,
// lights or view did. The programs really run (functionally, on every PP, in fixed point) and are
// recorded as PpPassWork; their time comes from the operations they perform (sim/pixel_processors/pp_cost_model.h)
// when the timing engine (sim/timing/frame_engine.h) replays them on each renderer's clock.
//
// Not modelled yet: moving the volume into the backing stores (the ring brings it once, before any
// frame) and the commands that start each pass (they arrive over the ring from a GP).

#include "kernels/shared/pp_volume/shaded_codes.h"
#include "kernels/shared/pp_volume/shading_programs.h"
#include "kernels/shared/pp_volume/voxel_placement.h"
#include "kernels/shared/pp_volume/voxel_record.h"
#include "scene/reference/shaded_volume.h"
#include "scene/reference/shading_view.h"
#include "scene/render/classification.h"
#include "scene/render/shading.h"
#include "scene/volume/volume.h"
#include "sim/core/config.h"
#include "sim/core/param.h"
#include "sim/core/time.h"
#include "sim/machine/machine.h"
#include "sim/pixel_processors/pp_cost_model.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace pp5 {

// How the volume sits in the renderers' backing stores ("voxel_store.*"), for every kernel whose pixel
// processors hold the voxels: where each voxel goes and how many bits each of its fields takes.
struct VoxelStoreSettings {
    PlacementPolicy placement = PlacementPolicy::Bricks;
    VoxelRecordLayout layout;

    // Two groups under one prefix, so that a kernel that lays its own records out in the PPs (PERM)
    // declares only the widths it takes.
    static const ParamGroup& placement_params();
    static const ParamGroup& layout_params();
    static VoxelStoreSettings from(const MachineConfig& config);
};

// One program's pass as a frame's report shows it: whether it ran, and its timing.
struct PpProgramPass : PpPassTiming {
    bool ran = false;
    PpProgramPass() = default;
    explicit PpProgramPass(const PpPassTiming& timing) : PpPassTiming(timing), ran(true) {}
};

// The passes a frame's classification and shading ran, in order.
struct PpFrameWork {
    std::optional<PpPassWork> classification;
    std::optional<PpPassWork> stationary_lights;  // Levoy's precomputed stationary lights, before the shading
    std::optional<PpPassWork> shading;
};

struct PpFrameReport {
    PpProgramPass classification;
    PpProgramPass stationary_lights;
    PpProgramPass shading;
    Tick start_ps = 0;
    Tick end_ps = 0;
    Tick duration_ps() const { return end_ps - start_ps; }
};

class PpShading {
public:
    // Places and loads the volume. Refuses "renderer.backing_store_bits" (reject_field, saying what it
    // would need) if it does not fit, and InputError for a layout the programs cannot use.
    PpShading(Machine& machine, const Volume& volume, const VoxelStoreSettings& settings);
    // The same refusal for a volume of `dims`, before it is read.
    static void check_fits(const Machine& machine, glm::ivec3 dims, const VoxelStoreSettings& settings);

    // Runs the passes this frame needs and times them on the machine from its current time (the
    // classification, then the shading); returns what they did.
    PpFrameReport update(const Classification& classification, const ColorMap& color_map, const PhongLighting& lighting,
                         const ShadingView& view, bool classification_changed, bool shading_changed);
    // The functional half of update(): the programs' runs, recorded.
    PpFrameWork compute(const Classification& classification, const ColorMap& color_map, const PhongLighting& lighting,
                        const ShadingView& view, bool classification_changed, bool shading_changed);

    // When the record keeps the stationary lights' sum (layout.stationary_light_bits > 0), stores it
    // afresh if what it depends on changed since it was stored: the stationary lights, k_d, k_s, n, the
    // view's direction (with a highlight), or the gradients, as `rewrite` leaves them (the caller says
    // when its rewrite moved). Returns the pass it ran, or nothing when the stored sum still holds.
    // compute() calls it before shading without a rewrite; a caller that shades with a rewrite calls it
    // itself, with the same rewrite and the expressions the rewrite reads.
    using SlotSelector = std::function<bool(const SlotFrame&)>;
    using SlotExpressions = std::function<std::vector<QeeCoefficients>(const SlotFrame&)>;
    std::optional<PpPassWork> refresh_stationary_lights(const PhongLighting& lighting, const ShadingView& view,
                                                        const GradientRewrite& rewrite = {},
                                                        const SlotExpressions& expressions = {},
                                                        bool rewrite_changed = false);

    // The PPs of a slot a program must run on, given its frame and expressions; every other PP must be
    // a bystander of the program (PpArray::run_candidates).
    using SlotCandidates =
        std::function<void(const SlotFrame&, std::span<const QeeCoefficients>, std::vector<int>& candidates)>;

    // Runs `program` on every renderer over the slots `select` accepts, each with the QEE expressions
    // `expressions` gives for its frame (none when empty), and records what each renderer ran. With
    // `candidates`, the host runs only those PPs of each slot; the work recorded is the same.
    PpPassWork execute(std::shared_ptr<const PpProgram> program, const SlotSelector& select,
                       const SlotExpressions& expressions, const SlotCandidates& candidates = {});
    PpPassWork execute(const PpProgram& program, const SlotSelector& select, const SlotExpressions& expressions) {
        return execute(std::make_shared<const PpProgram>(program), select, expressions);
    }
    PpProgramInputs program_inputs() const;

    // The colour and opacity codes the PPs hold, read back into `into`, reusing its storage: a
    // reshade then never holds two copies at once.
    void read_shaded_codes(ShadedCodes& into) const;
    // The same, decoded to floats: for the reference compositor and for tests.
    ShadedVolume shaded_volume() const;

    const VoxelPlacement& placement() const { return placement_; }
    const VoxelQuantization& quantization() const { return quantization_; }

private:
    PpPassWork execute_program(const PpProgram& program, const ShadingView* view);
    // Writes every voxel's value and gradient code into its slot; the gradients are not kept after.
    void load_volume(const Volume& volume);

    Machine& machine_;
    VoxelStoreSettings settings_;
    glm::ivec3 dims_;
    glm::vec3 spacing_;
    VoxelQuantization quantization_;
    VoxelPlacement placement_;

    // What the stored stationary-light sum was computed for.
    struct StationaryLightKey {
        std::vector<StationaryLight> lights;
        float diffuse = 0, specular = 0, shininess = 0;
        glm::vec3 forward{0.0f};  // only with a highlight
        bool rewritten = false;

        bool operator==(const StationaryLightKey&) const = default;
    };
    std::optional<StationaryLightKey> stationary_for_;
};

}  // namespace pp5
