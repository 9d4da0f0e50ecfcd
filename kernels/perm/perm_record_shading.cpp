#include "kernels/perm/perm_record_shading.h"

#include "scene/reference/shading_view.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace pp5 {

namespace {

std::uint64_t mask(int bits) { return bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1; }

}  // namespace

std::uint64_t PermRecordShading::backing_store_bits_needed(std::uint64_t positions_on_renderer, int pps,
                                                           const VoxelRecordLayout& layout) {
    const std::uint64_t slots =
        (positions_on_renderer + static_cast<std::uint64_t>(pps) - 1) / static_cast<std::uint64_t>(pps);
    return slots * static_cast<std::uint64_t>(layout.bits());
}

PhongLighting PermRecordShading::lighting_on_pps(const PhongLighting& lighting) {
    PhongLighting pps = lighting;
    pps.depth_cue_k1 = 1.0f;
    pps.depth_cue_k2 = 0.0f;
    return pps;
}

PermRecordShading::PermRecordShading(Machine& machine, const PermStructure& structure, glm::vec3 spacing,
                                     const VoxelRecordLayout& layout,
                                     const std::function<std::uint32_t(std::uint32_t)>& renderer_of)
    : machine_(machine),
      structure_(structure),
      spacing_(spacing),
      layout_(layout),
      quantization_(VoxelQuantization::for_ranges(structure.value_min(), structure.value_max(),
                                                  structure.integer_values(), structure.largest_gradient(), layout)),
      per_record_(structure.density_positions_per_record()) {
    auto& renderers = machine_.renderers();
    records_.resize(renderers.size());
    for (std::uint32_t c = 0; c < structure.candidates(); ++c) records_[renderer_of(c)].push_back(c);
    positions_ = structure.candidates() * static_cast<std::uint64_t>(per_record_);
    slots_.resize(renderers.size());
    for (std::size_t r = 0; r < renderers.size(); ++r) {
        const PpArray& array = renderers[r]->array();
        const std::uint64_t on_renderer = records_[r].size() * static_cast<std::uint64_t>(per_record_);
        const std::uint64_t bits = backing_store_bits_needed(on_renderer, array.size(), layout_);
        if (bits > static_cast<std::uint64_t>(array.backing_store_bits()))
            reject_field(
                "renderer.backing_store_bits",
                fmt::format(
                    "the PP-shaded records need {} bits per PP on renderer {} ({} positions of {} bits over {} PPs), "
                    "more than its {}; quantize the density more coarsely (perm.density_positions), add renderers "
                    "or backing store, or shade on the GPs (perm.shading = \"gp\")",
                    bits, r, on_renderer, layout_.bits(), array.size(), array.backing_store_bits()));
        slots_[r] = static_cast<int>(bits / static_cast<std::uint64_t>(layout_.bits()));
    }
    // Load: position e of renderer r (its records' positions in order) goes to PP e mod P of slot e / P.
    pp5::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        PpArray& array = renderers[r]->array();
        const auto pps = static_cast<std::uint64_t>(array.size());
        // The record fields of the slot being filled: value, then the gradient's three axes.
        std::vector<PpBackingWriter> fields;
        std::uint64_t e = 0;
        for (const std::uint32_t candidate : records_[r])
            for (int position = 0; position < per_record_; ++position, ++e) {
                const PermStructure::Sample s = structure_.at_density_position(candidate, position);
                const int pp = static_cast<int>(e % pps);
                if (pp == 0) {
                    const int base = static_cast<int>(e / pps) * layout_.bits();
                    fields = {array.backing_writer(base + layout_.value_offset(), layout_.value_bits),
                              array.backing_writer(base + layout_.gradient_offset(0), layout_.gradient_bits),
                              array.backing_writer(base + layout_.gradient_offset(1), layout_.gradient_bits),
                              array.backing_writer(base + layout_.gradient_offset(2), layout_.gradient_bits)};
                }
                fields[0].write(pp, static_cast<std::uint64_t>(quantization_.value_code(s.value)));
                for (int axis = 0; axis < 3; ++axis)
                    fields[static_cast<std::size_t>(axis) + 1].write(
                        pp, static_cast<std::uint64_t>(quantization_.gradient_code(s.gradient[axis])) &
                                mask(layout_.gradient_bits));
            }
        renderers[r]->set_backing_store_bits_used(static_cast<std::uint64_t>(slots_[r]) *
                                                  static_cast<std::uint64_t>(layout_.bits()));
    });
    results_.assign(positions_ * 4, 0);
}

PpPassWork PermRecordShading::run(const PpProgram& program) {
    if (program.expressions > 0)
        throw std::logic_error("PERM's PP programs cannot use the QEE: records are not laid out in space");
    auto& renderers = machine_.renderers();
    PpPassWork work{std::make_shared<const PpProgram>(program), std::vector<std::uint64_t>(renderers.size(), 0),
                    std::vector<PpRunCounts>(renderers.size())};
    // Each renderer runs over its own slots only, so the thread count changes nothing.
    pp5::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        PpArray& array = renderers[r]->array();
        for (int slot = 0; slot < slots_[r]; ++slot) {
            PpSlotContext context;
            context.record_base_bit = slot * layout_.bits();
            work.counts[r] += array.run(program, context);
            ++work.slots[r];
        }
    });
    return work;
}

PpPassWork PermRecordShading::classify(const Classification& classification) {
    const PpProgramInputs inputs{layout_, quantization_, glm::vec3(1.0f), machine_.shape().local_memory_bits};
    return run(build_classification_program(classification, inputs));
}

PpPassWork PermRecordShading::shade(const ColorMap& colors, const PhongLighting& lighting, glm::vec3 view_forward) {
    // Gradients are per voxel: an anisotropic volume's normals are corrected by the spacing the
    // structure was built on, as the voxel store's are.
    const PpProgramInputs inputs{layout_, quantization_, spacing_, machine_.shape().local_memory_bits};
    ShadingView distant;
    distant.projection = Projection::Parallel;
    distant.forward = view_forward;
    return run(build_shading_program(colors, lighting_on_pps(lighting), distant, inputs));
}

void PermRecordShading::read_back() {
    auto& renderers = machine_.renderers();
    pp5::parallel_for(std::size_t{0}, renderers.size(), [&](std::size_t r) {
        const PpArray& array = renderers[r]->array();
        const auto pps = static_cast<std::uint64_t>(array.size());
        // The shaded fields of the slot being read: red, green, blue, opacity.
        std::vector<PpBackingReader> channels;
        std::uint64_t e = 0;
        for (const std::uint32_t candidate : records_[r])
            for (int position = 0; position < per_record_; ++position, ++e) {
                const int pp = static_cast<int>(e % pps);
                if (pp == 0) {
                    const int base = static_cast<int>(e / pps) * layout_.bits();
                    channels = {array.backing_reader(base + layout_.color_offset(0), layout_.color_bits),
                                array.backing_reader(base + layout_.color_offset(1), layout_.color_bits),
                                array.backing_reader(base + layout_.color_offset(2), layout_.color_bits),
                                array.backing_reader(base + layout_.opacity_offset(), layout_.opacity_bits)};
                }
                std::uint16_t* out =
                    &results_[(static_cast<std::uint64_t>(candidate) * static_cast<std::uint64_t>(per_record_) +
                               static_cast<std::uint64_t>(position)) *
                              4];
                for (std::size_t c = 0; c < 4; ++c) out[c] = static_cast<std::uint16_t>(channels[c].read(pp));
            }
    });
}

glm::vec4 PermRecordShading::at(std::uint32_t candidate, int position) const {
    const std::uint16_t* in =
        &results_[(static_cast<std::uint64_t>(candidate) * static_cast<std::uint64_t>(per_record_) +
                   static_cast<std::uint64_t>(position)) *
                  4];
    const float color_max = static_cast<float>(mask(layout_.color_bits));
    const float opacity_max = static_cast<float>(mask(layout_.opacity_bits));
    return {static_cast<float>(in[0]) / color_max, static_cast<float>(in[1]) / color_max,
            static_cast<float>(in[2]) / color_max, static_cast<float>(in[3]) / opacity_max};
}

std::uint32_t PermRecordShading::fetched_words(bool with_density) const {
    const int density_bits = with_density ? 8 * structure_.memory().density_bytes : 0;
    const std::uint64_t bits = static_cast<std::uint64_t>(per_record_) *
                               static_cast<std::uint64_t>(3 * layout_.color_bits + layout_.opacity_bits + density_bits);
    return static_cast<std::uint32_t>((bits + 31) / 32);
}

}  // namespace pp5
