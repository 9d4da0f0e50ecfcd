#include "sim/timing/one_processor.h"

#include "sim/timing/frame_engine.h"

namespace pp5 {

FrameTiming time_frame_on_one_processor(const MachineConfig& config, const FrameWork& work) {
    const std::vector<Tick> cost = gp_op_costs(config, work.op_kinds);
    const auto sum = [&](const std::vector<GpOp>& ops, std::uint32_t first, std::uint32_t count) {
        Tick t = 0;
        for (std::uint32_t i = first; i < first + count; ++i)
            t += static_cast<Tick>(ops[i].count) * cost.at(ops[i].kind);
        return t;
    };
    const auto sum_all = [&](const std::vector<GpOp>& ops) {
        return sum(ops, 0, static_cast<std::uint32_t>(ops.size()));
    };

    FrameTiming timing;
    Tick t = 0;
    for (const Phase& phase : work.phases) {
        PhaseTiming p;
        p.name = phase.name;
        p.start_ps = t;
        if (const auto* pp = std::get_if<PpPhase>(&phase.work)) {
            for (const PpPhase::Pass& pass : pp->passes) {
                PpPassTiming done;
                done.start_ps = t;
                done.end_ps = t += sum_all(pass.on_one_processor);
                done.instructions = pass.work.program->instructions.size();
                p.passes.push_back(done);
            }
        } else if (const auto* broadcast = std::get_if<BroadcastPhase>(&phase.work)) {
            t += sum_all(broadcast->then_each_gp);
        } else {
            // Each group's tasks, then the next group's: a group ends when its last task's work is done.
            const GpPhase& gp = std::get<GpPhase>(phase.work);
            std::vector<Tick> group_work(gp.groups, 0);
            for (const GpTask& task : gp.tasks) {
                Tick w =
                    sum(gp.ops, task.first_op, task.op_count) + sum(gp.ops, task.first_finish_op, task.finish_op_count);
                for (std::uint32_t i = task.first_item; i < task.first_item + task.item_count; ++i) {
                    const GpItem& item = gp.items[i];
                    for (std::uint32_t s = item.first_step; s < item.first_step + item.step_count; ++s)
                        w += sum(gp.ops, gp.steps[s].first_op, gp.steps[s].op_count);
                }
                group_work.at(task.group) += w;
                p.gp.items += task.item_count;
            }
            // A lone processor also draws what the renderers would have drawn, after the last group.
            if (!group_work.empty()) group_work.back() += sum_all(gp.regions_on_one_processor);
            else t += sum_all(gp.regions_on_one_processor);
            for (const Tick w : group_work) p.group_end_ps.push_back(t += w);
            p.gp.gp_busy = t - p.start_ps;
        }
        p.end_ps = t;
        timing.phases.push_back(std::move(p));
    }
    timing.end_ps = t;
    return timing;
}

}  // namespace pp5
