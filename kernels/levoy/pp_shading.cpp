#include "kernels/levoy/pp_shading.h"

#include "sim/core/input_error.h"
#include "sim/timing/frame_engine.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace pp5 {

namespace {

constexpr const char* kMachineFile = "machine configuration";

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
    const MachineConfig& c = machine.config();
    return {static_cast<int>(c.integer("renderer.count")), static_cast<int>(c.integer("renderer.pp_columns")),
            static_cast<int>(c.integer("renderer.pp_rows")), static_cast<int>(c.integer("renderer.backing_store_bits"))};
}

}  // namespace

const ParamGroup& LevoySettings::params() {
    static const ParamGroup group = [] {
        ParamGroup g("levoy", "Levoy's volume rendering kernel: the volume in the pixel processors, the GPs' ray casting");
        g.text("placement", "bricks", {"bricks", "slices"},
               "Which renderer, PP and slot holds each voxel: solid bricks per renderer, or z-slices dealt round-robin",
               Provenance::Default, "pp5sim: Levoy gives each PP 64 voxels but not their arrangement")
            .integer("value_bits", 8, "bits", 1, 16, "Bits of each voxel's scalar value in the backing store",
                     Provenance::Paper, "Levoy 1989: 8 bytes per voxel for value, gradient, colour and opacity")
            .integer("gradient_bits", 8, "bits", 2, 16, "Bits of each signed gradient component",
                     Provenance::Default, "pp5sim: one byte each fills Levoy's 8-byte budget")
            .integer("color_bits", 8, "bits", 1, 16, "Bits of each shaded colour channel", Provenance::Default,
                     "pp5sim: one byte each fills Levoy's 8-byte budget")
            .integer("opacity_bits", 8, "bits", 1, 16, "Bits of each voxel's opacity", Provenance::Default,
                     "pp5sim: one byte fills Levoy's 8-byte budget")
            .integer("block_cells", 4, "cells", 1, 64,
                     "Cells along each edge of the block one voxel request asks for ((n+1)^3 voxels)", Provenance::Default,
                     "Levoy 1989: GPs 'request sets of voxels', size not given")
            .text("ray_assignment", "static_tiles", {"static_tiles", "work_queue"},
                  "Which GP casts which rays: tiles dealt round-robin, or handed out by the host as GPs ask",
                  Provenance::Default, "Levoy 1989: 'each is assigned a set of rays', policy not given")
            .integer("tile_pixels", 16, "pixels", 1, 4096, "Edge of the square tiles of rays a GP works on",
                     Provenance::Default, "pp5sim")
            .integer("refinement_spacing", 8, "pixels", 1, 1024, "Pixels between the rays of the first, sparse pass",
                     Provenance::Paper, "Levoy 1990 (adaptive refinement): one ray per 4x4 or 8x8 pixels first")
            .real("refinement_threshold", 0.1, "colour", -1, 1,
                  "A square splits when its corners differ by more than this in r, g or b (0-1); below 0 every pixel is cast",
                  Provenance::Default, "Levoy 1990 uses a colour-difference threshold; its value is ours")
            .boolean("pyramid_skipping", true, "Skip empty space with the pyramid of binary volumes", Provenance::Paper,
                     "Levoy 1989 and 1990: hierarchical spatial enumeration")
            .boolean("depth_buffer", true,
                     "While the observer and the set of non-empty voxels stay, start rays at the first non-empty sample "
                     "found in an earlier frame",
                     Provenance::Paper, "Levoy 1989: record the depth of the first non-empty voxel along each ray")
            .integer("jitter_samples", 16, "count", 1, 1024,
                     "Subvoxel translations of each polygon in 3D scan-conversion (1: binary voxelisation)", Provenance::Default,
                     "Levoy 1989: 'moved through a set of subvoxel-sized translations', count not given");
        return g;
    }();
    return group;
}

LevoySettings LevoySettings::from(const MachineConfig& config) {
    LevoySettings s;
    s.placement = parse_placement_policy(config.text("levoy.placement")).value_or(PlacementPolicy::Bricks);
    s.layout.value_bits = static_cast<int>(config.integer("levoy.value_bits"));
    s.layout.gradient_bits = static_cast<int>(config.integer("levoy.gradient_bits"));
    s.layout.color_bits = static_cast<int>(config.integer("levoy.color_bits"));
    s.layout.opacity_bits = static_cast<int>(config.integer("levoy.opacity_bits"));
    s.block_cells = static_cast<int>(config.integer("levoy.block_cells"));
    s.ray_assignment = config.text("levoy.ray_assignment") == "work_queue" ? TaskAssignment::WorkQueue : TaskAssignment::Static;
    s.tile_pixels = static_cast<int>(config.integer("levoy.tile_pixels"));
    s.refinement.initial_spacing = static_cast<int>(config.integer("levoy.refinement_spacing"));
    s.refinement.threshold = static_cast<float>(config.real("levoy.refinement_threshold"));
    s.pyramid_skipping = config.boolean("levoy.pyramid_skipping");
    s.depth_buffer = config.boolean("levoy.depth_buffer");
    s.jitter_samples = static_cast<int>(config.integer("levoy.jitter_samples"));
    return s;
}

PpShading::PpShading(Machine& machine, const Volume& volume, const LevoySettings& settings)
    : machine_(machine),
      settings_(settings),
      dims_(volume.dims()),
      spacing_(volume.spacing()),
      gradients_(compute_gradients(volume)),
      quantization_(VoxelQuantization::choose(volume, gradients_, settings.layout)),
      placement_(settings.placement, volume.dims(), shape_of(machine), settings.layout.bits()) {
    if (!placement_.fits()) throw InputError(kMachineFile, "renderer.backing_store_bits", placement_.shortfall());
    load_volume(volume);
}

void PpShading::load_volume(const Volume& volume) {
    const VoxelRecordLayout& layout = settings_.layout;
    const int record_bits = layout.bits();
    auto& renderers = machine_.renderers();
    tbb::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        PpArray& array = renderers[r]->array();
        const int renderer = static_cast<int>(r);
        for (int slot = 0; slot < placement_.slots_needed(); ++slot) {
            const SlotFrame frame = placement_.frame(renderer, slot);
            if (!frame.used) continue;
            const int base = slot * record_bits;
            for_each_voxel(frame, dims_, placement_.shape(), [&](int pp, glm::ivec3 v) {
                const std::size_t i = volume.index(v.x, v.y, v.z);
                array.write_backing(pp, base + layout.value_offset(), layout.value_bits,
                                    static_cast<std::uint64_t>(quantization_.value_code(volume.samples()[i])));
                const glm::vec3 g = gradients_.gradients[i];
                for (int axis = 0; axis < 3; ++axis) {
                    const auto code = static_cast<std::uint64_t>(quantization_.gradient_code(g[axis]));
                    array.write_backing(pp, base + layout.gradient_offset(axis), layout.gradient_bits, code & mask(layout.gradient_bits));
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
    return execute(program, [](const SlotFrame&) { return true; }, expressions);
}

PpProgramInputs PpShading::program_inputs() const {
    return PpProgramInputs{settings_.layout, quantization_, spacing_, static_cast<int>(machine_.config().integer("renderer.local_memory_bits"))};
}

PpPassWork PpShading::execute(const PpProgram& program, const SlotSelector& select, const SlotExpressions& expressions) {
    auto& renderers = machine_.renderers();
    const int record_bits = settings_.layout.bits();
    PpPassWork work{program, std::vector<std::uint64_t>(renderers.size(), 0), std::vector<PpRunCounts>(renderers.size())};
    // Every renderer's PPs run the program over their slots (renderers in parallel; each renderer's
    // result depends on its own data only, so the thread count changes nothing).
    tbb::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        PpArray& array = renderers[r]->array();
        for (int slot = 0; slot < placement_.slots_needed(); ++slot) {
            const SlotFrame frame = placement_.frame(static_cast<int>(r), slot);
            if (!frame.used || !select(frame)) continue;
            std::vector<QeeCoefficients> coefficients;
            if (expressions) coefficients = expressions(frame);
            PpSlotContext context;
            context.record_base_bit = slot * record_bits;
            context.expressions = coefficients;
            work.counts[r] += array.run(program, context);
            ++work.slots[r];
        }
    });
    return work;
}

PpFrameReport PpShading::update(const Classification& classification, const ColorMap& color_map,
                                const PhongLighting& lighting, const ShadingView& view, bool classification_changed,
                                bool shading_changed) {
    const PpFrameWork work = compute(classification, color_map, lighting, view, classification_changed, shading_changed);
    FrameWork frame;
    if (work.classification) frame.phases.push_back(Phase{"classification", PpPhase{{PpPhase::Pass{*work.classification, 0, {}}}}});
    if (work.shading) frame.phases.push_back(Phase{"shading", PpPhase{{PpPhase::Pass{*work.shading, 0, {}}}}});
    const FrameTiming timing = time_frame(machine_, frame);
    PpFrameReport report;
    report.start_ps = timing.start_ps;
    report.end_ps = timing.end_ps;
    if (const PhaseTiming* p = timing.phase("classification")) report.classification = PpProgramPass(p->passes.front());
    if (const PhaseTiming* p = timing.phase("shading")) report.shading = PpProgramPass(p->passes.front());
    return report;
}

PpFrameWork PpShading::compute(const Classification& classification, const ColorMap& color_map, const PhongLighting& lighting,
                               const ShadingView& view, bool classification_changed, bool shading_changed) {
    const PpProgramInputs inputs = program_inputs();
    PpFrameWork work;
    if (classification_changed) work.classification = execute_program(build_classification_program(classification, inputs), nullptr);
    if (shading_changed) {
        const PpProgram program = build_shading_program(color_map, lighting, view, inputs);
        work.shading = execute_program(program, program.expressions > 0 ? &view : nullptr);
    }
    return work;
}

ShadedVolume PpShading::shaded_volume() const {
    const VoxelRecordLayout& layout = settings_.layout;
    const int record_bits = layout.bits();
    ShadedVolume shaded{dims_, spacing_, std::vector<glm::vec4>(static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z)};
    const float color_max = static_cast<float>(mask(layout.color_bits));
    const float opacity_max = static_cast<float>(mask(layout.opacity_bits));
    auto& renderers = machine_.renderers();
    tbb::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        const PpArray& array = renderers[r]->array();
        for (int slot = 0; slot < placement_.slots_needed(); ++slot) {
            const SlotFrame frame = placement_.frame(static_cast<int>(r), slot);
            if (!frame.used) continue;
            const int base = slot * record_bits;
            for_each_voxel(frame, dims_, placement_.shape(), [&](int pp, glm::ivec3 v) {
                glm::vec4 rgba;
                for (int c = 0; c < 3; ++c) {
                    rgba[c] = static_cast<float>(array.read_backing(pp, base + layout.color_offset(c), layout.color_bits)) / color_max;
                }
                rgba.a = static_cast<float>(array.read_backing(pp, base + layout.opacity_offset(), layout.opacity_bits)) / opacity_max;
                shaded.rgba[static_cast<std::size_t>(v.x) + static_cast<std::size_t>(dims_.x) *
                                (static_cast<std::size_t>(v.y) + static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(v.z))] = rgba;
            });
        }
    });
    return shaded;
}

}  // namespace pp5
