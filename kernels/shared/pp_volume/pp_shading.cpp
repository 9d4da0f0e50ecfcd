#include "kernels/shared/pp_volume/pp_shading.h"

#include "scene/reference/gradient_field.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"
#include "sim/timing/frame_engine.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace pp5 {

namespace {

std::uint64_t mask(int bits) { return bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1; }

// Calls visit(pp, voxel) for every PP of `frame` that holds a voxel of a volume of `dims`.
template <class Visit>
void for_each_voxel(const SlotFrame& frame, glm::ivec3 dims, const PpArrayShape& shape, Visit&& visit) {
    const int columns = std::min(shape.columns, dims.x - frame.origin.x);
    const int rows = std::min(shape.rows, dims.y - frame.origin.y);
    for (int row = 0; row < rows; ++row) {
        for (int column = 0; column < columns; ++column) {
            visit(column + row * shape.columns, frame.origin + glm::ivec3(column, row, 0));
        }
    }
}

PpArrayShape shape_of(const Machine& machine) {
    const MachineShape& m = machine.shape();
    return {m.renderers, m.pp_columns, m.pp_rows, m.backing_store_bits};
}

void refuse_unless_placed(const VoxelPlacement& placement) {
    if (!placement.fits()) reject_field("renderer.backing_store_bits", placement.shortfall());
}

}  // namespace

const ParamGroup& VoxelStoreSettings::placement_params() {
    static const ParamGroup group = [] {
        ParamGroup g("voxel_store", "Where the renderers' backing stores hold each voxel");
        g.text("placement", "bricks", {"bricks", "slices"},
               "Which renderer, PP and slot holds each voxel: solid bricks per renderer, or z-slices dealt round-robin",
               Provenance::Default, "pp5sim: Levoy gives each PP 64 voxels but not their arrangement");
        return g;
    }();
    return group;
}

const ParamGroup& VoxelStoreSettings::layout_params() {
    static const ParamGroup group = [] {
        ParamGroup g("voxel_store", "The bits of each voxel's fields in the renderers' backing stores");
        g.integer("value_bits", 8, "bits", 1, 16, "Bits of each voxel's scalar value in the backing store",
                  Provenance::Default,
                  "pp5sim: one byte, as the 8-bit volumes are; Levoy 1989 gives 8 bytes a voxel for value, "
                  "gradient, colour and "
                  "opacity together, not how they divide")
            .integer("gradient_bits", 8, "bits", 2, 16, "Bits of each signed gradient component", Provenance::Default,
                     "pp5sim: one byte each fills Levoy's 8-byte budget")
            .integer("color_bits", 8, "bits", 1, 16, "Bits of each shaded colour channel", Provenance::Default,
                     "pp5sim: one byte each fills Levoy's 8-byte budget")
            .integer("opacity_bits", 8, "bits", 1, 16, "Bits of each voxel's opacity", Provenance::Default,
                     "pp5sim: one byte fills Levoy's 8-byte budget");
        return g;
    }();
    return group;
}

VoxelStoreSettings VoxelStoreSettings::from(const MachineConfig& config) {
    VoxelStoreSettings s;
    s.placement = parse_placement_policy(config.text("voxel_store.placement")).value_or(PlacementPolicy::Bricks);
    s.layout.value_bits = static_cast<int>(config.integer("voxel_store.value_bits"));
    s.layout.gradient_bits = static_cast<int>(config.integer("voxel_store.gradient_bits"));
    s.layout.color_bits = static_cast<int>(config.integer("voxel_store.color_bits"));
    s.layout.opacity_bits = static_cast<int>(config.integer("voxel_store.opacity_bits"));
    return s;
}

PpShading::PpShading(Machine& machine, const Volume& volume, const VoxelStoreSettings& settings)
    : machine_(machine),
      settings_(settings),
      dims_(volume.dims()),
      spacing_(volume.spacing()),
      placement_(settings.placement, volume.dims(), shape_of(machine), settings.layout.bits()) {
    refuse_unless_placed(placement_);
    quantization_ = VoxelQuantization::choose(volume, settings.layout);
    load_volume(volume);
}

// Each voxel's gradient is computed as its record is written: a float gradient field would take 12
// bytes a voxel (1.6 GB at 512^3) only to be turned into codes once.
void PpShading::check_fits(const Machine& machine, glm::ivec3 dims, const VoxelStoreSettings& settings) {
    refuse_unless_placed(VoxelPlacement(settings.placement, dims, shape_of(machine), settings.layout.bits()));
}

void PpShading::load_volume(const Volume& volume) {
    const VoxelRecordLayout& layout = settings_.layout;
    const int record_bits = layout.bits();
    auto& renderers = machine_.renderers();
    pp5::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        PpArray& array = renderers[r]->array();
        const int renderer = static_cast<int>(r);
        for (int slot = 0; slot < placement_.slots_needed(); ++slot) {
            const SlotFrame frame = placement_.frame(renderer, slot);
            if (!frame.used) continue;
            const int base = slot * record_bits;
            const PpBackingWriter value = array.backing_writer(base + layout.value_offset(), layout.value_bits);
            const PpBackingWriter gradient[3] = {
                array.backing_writer(base + layout.gradient_offset(0), layout.gradient_bits),
                array.backing_writer(base + layout.gradient_offset(1), layout.gradient_bits),
                array.backing_writer(base + layout.gradient_offset(2), layout.gradient_bits)};
            for_each_voxel(frame, dims_, placement_.shape(), [&](int pp, glm::ivec3 v) {
                const std::size_t i = volume.index(v.x, v.y, v.z);
                value.write(pp, static_cast<std::uint64_t>(quantization_.value_code(volume.samples()[i])));
                const glm::vec3 g = central_difference(volume, v);
                for (int axis = 0; axis < 3; ++axis) {
                    const auto code = static_cast<std::uint64_t>(quantization_.gradient_code(g[axis]));
                    gradient[axis].write(pp, code & mask(layout.gradient_bits));
                }
            });
        }
        renderers[r]->set_backing_store_bits_used(static_cast<std::uint64_t>(placement_.slots_used(renderer)) *
                                                  static_cast<std::uint64_t>(record_bits));
    });
}

PpPassWork PpShading::execute_program(const PpProgram& program, const ShadingView* view) {
    SlotExpressions expressions;
    if (view != nullptr) {
        expressions = [&](const SlotFrame& frame) {
            const auto e = slot_expressions(*view, frame, spacing_);
            return std::vector<QeeCoefficients>(e.begin(), e.end());
        };
    }
    return execute(
        program, [](const SlotFrame&) { return true; }, expressions);
}

PpProgramInputs PpShading::program_inputs() const {
    return PpProgramInputs{settings_.layout, quantization_, spacing_, machine_.shape().local_memory_bits};
}

PpPassWork PpShading::execute(std::shared_ptr<const PpProgram> shared, const SlotSelector& select,
                              const SlotExpressions& expressions, const SlotCandidates& candidates) {
    const PpProgram& program = *shared;
    auto& renderers = machine_.renderers();
    const int record_bits = settings_.layout.bits();
    PpPassWork work{std::move(shared), std::vector<std::uint64_t>(renderers.size(), 0),
                    std::vector<PpRunCounts>(renderers.size())};
    // Every renderer's PPs run the program over their slots (renderers in parallel; each renderer's
    // result depends on its own data only, so the thread count changes nothing).
    pp5::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        PpArray& array = renderers[r]->array();
        std::vector<int> listed;
        for (int slot = 0; slot < placement_.slots_needed(); ++slot) {
            const SlotFrame frame = placement_.frame(static_cast<int>(r), slot);
            if (!frame.used || !select(frame)) continue;
            std::vector<QeeCoefficients> coefficients;
            if (expressions) coefficients = expressions(frame);
            PpSlotContext context;
            context.record_base_bit = slot * record_bits;
            context.expressions = coefficients;
            if (candidates) {
                candidates(frame, coefficients, listed);
                work.counts[r] += array.run_candidates(program, context, listed);
            } else {
                work.counts[r] += array.run(program, context);
            }
            ++work.slots[r];
        }
    });
    return work;
}

PpFrameReport PpShading::update(const Classification& classification, const ColorMap& color_map,
                                const PhongLighting& lighting, const ShadingView& view, bool classification_changed,
                                bool shading_changed) {
    const PpFrameWork work =
        compute(classification, color_map, lighting, view, classification_changed, shading_changed);
    FrameWork frame;
    if (work.classification)
        frame.phases.push_back(Phase{"classification", PpPhase{{PpPhase::Pass{*work.classification, 0, {}}}}});
    if (work.stationary_lights)
        frame.phases.push_back(Phase{"stationary_lights", PpPhase{{PpPhase::Pass{*work.stationary_lights, 0, {}}}}});
    if (work.shading) frame.phases.push_back(Phase{"shading", PpPhase{{PpPhase::Pass{*work.shading, 0, {}}}}});
    const FrameTiming timing = time_frame(machine_, frame);
    PpFrameReport report;
    report.start_ps = timing.start_ps;
    report.end_ps = timing.end_ps;
    if (const PhaseTiming* p = timing.phase("classification")) report.classification = PpProgramPass(p->passes.front());
    if (const PhaseTiming* p = timing.phase("stationary_lights"))
        report.stationary_lights = PpProgramPass(p->passes.front());
    if (const PhaseTiming* p = timing.phase("shading")) report.shading = PpProgramPass(p->passes.front());
    return report;
}

PpFrameWork PpShading::compute(const Classification& classification, const ColorMap& color_map,
                               const PhongLighting& lighting, const ShadingView& view, bool classification_changed,
                               bool shading_changed) {
    const PpProgramInputs inputs = program_inputs();
    PpFrameWork work;
    if (classification_changed)
        work.classification = execute_program(build_classification_program(classification, inputs), nullptr);
    if (shading_changed) {
        work.stationary_lights = refresh_stationary_lights(lighting, view);
        const PpProgram program = build_shading_program(color_map, lighting, view, inputs);
        work.shading = execute_program(program, program.expressions > 0 ? &view : nullptr);
    }
    return work;
}

std::optional<PpPassWork> PpShading::refresh_stationary_lights(const PhongLighting& lighting, const ShadingView& view,
                                                               const GradientRewrite& rewrite,
                                                               const SlotExpressions& expressions,
                                                               bool rewrite_changed) {
    if (settings_.layout.stationary_light_bits <= 0) return std::nullopt;
    if (lighting.stationary_lights.empty()) {
        // Nothing is stored now, and the gradients may change (a capping region moving) before the
        // lights come back: they will be summed afresh.
        stationary_for_.reset();
        return std::nullopt;
    }
    StationaryLightKey key{lighting.stationary_lights,
                           lighting.diffuse,
                           lighting.specular,
                           lighting.shininess,
                           lighting.specular > 0.0f ? view.forward : glm::vec3(0.0f),
                           static_cast<bool>(rewrite)};
    if (stationary_for_ == key && !rewrite_changed) return std::nullopt;
    const PpProgram program = build_stationary_light_program(lighting, view, program_inputs(), rewrite);
    stationary_for_ = std::move(key);
    if (expressions)
        return execute(
            program, [](const SlotFrame&) { return true; }, expressions);
    return execute_program(program, program.expressions > 0 ? &view : nullptr);
}

ShadedVolume PpShading::shaded_volume() const {
    ShadedCodes codes;
    read_shaded_codes(codes);
    return codes.decoded();
}

void PpShading::read_shaded_codes(ShadedCodes& shaded) const {
    const VoxelRecordLayout& layout = settings_.layout;
    const int record_bits = layout.bits();
    const auto color_max = static_cast<float>(mask(layout.color_bits));
    // Every voxel lies in a used slot, so each code is overwritten below.
    shaded.reset(dims_, spacing_,
                 glm::vec4(color_max, color_max, color_max, static_cast<float>(mask(layout.opacity_bits))));
    // Four 8-bit codes side by side are a u8vec4's bytes, in order (on a little-endian host): a run of
    // PPs is then copied as it is.
    const bool bytes_as_stored = std::endian::native == std::endian::little && shaded.narrow() &&
                                 layout.color_bits == 8 && layout.opacity_bits == 8;
    const PpArrayShape& shape = placement_.shape();
    auto& renderers = machine_.renderers();
    pp5::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        const PpArray& array = renderers[r]->array();
        std::vector<std::uint64_t> run(static_cast<std::size_t>(shape.columns));
        for (int slot = 0; slot < placement_.slots_needed(); ++slot) {
            const SlotFrame frame = placement_.frame(static_cast<int>(r), slot);
            if (!frame.used) continue;
            // The three colours and the opacity lie side by side, at most 64 bits: one read a voxel.
            const PpBackingReader codes = array.backing_reader(slot * record_bits + layout.color_offset(0),
                                                               3 * layout.color_bits + layout.opacity_bits);
            // A row of PPs holds a run of voxels along x (for_each_voxel's order).
            const int columns = std::min(shape.columns, dims_.x - frame.origin.x);
            const int rows = std::min(shape.rows, dims_.y - frame.origin.y);
            for (int row = 0; row < rows; ++row) {
                const std::span<std::uint64_t> bits(run.data(), static_cast<std::size_t>(columns));
                codes.read_run(row * shape.columns, bits);
                const glm::ivec3 v = frame.origin + glm::ivec3(0, row, 0);
                const std::size_t first = static_cast<std::size_t>(v.x) +
                                          static_cast<std::size_t>(dims_.x) *
                                              (static_cast<std::size_t>(v.y) +
                                               static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(v.z));
                if (bytes_as_stored) {
                    glm::u8vec4* out = shaded.narrow_codes_to_write() + first;
                    for (std::size_t i = 0; i < bits.size(); ++i) {
                        const auto word = static_cast<std::uint32_t>(bits[i]);
                        std::memcpy(&out[i], &word, sizeof word);
                    }
                    continue;
                }
                for (std::size_t i = 0; i < bits.size(); ++i) {
                    std::uint64_t b = bits[i];
                    glm::u16vec4 code;
                    for (int c = 0; c < 3; ++c, b >>= layout.color_bits)
                        code[c] = static_cast<std::uint16_t>(b & mask(layout.color_bits));
                    code[3] = static_cast<std::uint16_t>(b & mask(layout.opacity_bits));
                    shaded.set(first + i, code);
                }
            }
        }
    });
}

}  // namespace pp5
