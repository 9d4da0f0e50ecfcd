// The renderers answering fetches and drawing their regions, the frame buffer, the host's work queue.
#include "sim/timing/engine_agents.h"

#include <fmt/format.h>

#include <algorithm>

namespace pp5::engine {

std::uint32_t RendererAgent::units_of(std::uint32_t block) const {
    for (const BlockPart& part : run_.phase.blocks->parts(block))
        if (part.renderer == renderer_.index()) return part.units;
    throw std::logic_error(fmt::format("{}: asked for a block it holds no part of", renderer_.name()));
}

RendererAgent::RendererAgent(GpPhaseRun& run, Renderer& renderer, std::size_t station)
    : run_(run), renderer_(renderer), station_(station) {
    if (renderer.index() < run.phase.regions.size()) region_ = &run.phase.regions[renderer.index()];
    if (region_ != nullptr && !region_->steps.empty()) arrived_.assign(run.phase.batches.size(), 0);
}

std::size_t RendererAgent::steps() const { return region_ == nullptr ? 0 : region_->steps.size(); }

void RendererAgent::begin(Tick start) {
    if (region_ == nullptr) run_.region_finished(start);  // no screen work here this phase
    else draw_next(start);
}

void RendererAgent::draw_next(Tick now) {
    if (drawing_) return;
    if (next_step_ < steps()) {
        const RegionStep& step = region_->steps[next_step_];
        if (step.batch != kNoBatch && !arrived_[step.batch]) return;  // the batch it draws is not in yet
        ++next_step_;
        const PpProgram& program = run_.phase.region_programs[step.program];
        const auto busy_before = renderer_.draw_busy_ps.value();
        const Tick end = renderer_.draw(now, program.name, run_.region_costs[renderer_.index()][step.program],
                                        step.runs, step.write_words, program.local_memory_bits_used);
        run_.timing.gp.primitives_drawn += step.runs;
        run_.timing.gp.renderer_drawing[renderer_.index()] +=
            static_cast<Tick>(renderer_.draw_busy_ps.value() - busy_before);
        drawing_ = true;
        run_.machine.events().schedule(end, *this, pack(Signal::Resume, 0, 0));
        return;
    }
    if (read_out_) return;
    read_out_ = true;
    if (region_->readout_pixels > 0) {
        ++run_.pixel_messages_in_flight;
        RingNetwork& ring = run_.machine.ring();
        ring.send(run_.machine.events(), std::max(now, renderer_.busy_until()),
                  RingMessage{MessageKind::PixelBlock, station_, run_.frame_buffer_station,
                              region_->readout_pixels * static_cast<std::uint64_t>(run_.pixel_bits), false},
                  *run_.frame_buffer, kReadout | renderer_.index());
    }
    run_.region_finished(now);
}

std::string RendererAgent::describe_stall() const {
    if (region_done()) return {};
    if (drawing_) return fmt::format(" {} is drawing step {};", renderer_.name(), next_step_ - 1);
    return fmt::format(" {} waits for batch {} (region step {} of {});", renderer_.name(),
                       region_->steps[next_step_].batch, next_step_, steps());
}

void RendererAgent::handle_event(Tick now, std::uint64_t payload) {
    if (signal_of(payload) == Signal::Task) {  // a batch for this renderer's region has arrived
        const auto batch = static_cast<std::uint32_t>(value_of(payload));
        if (arrived_.empty())
            throw std::logic_error(
                fmt::format("{}: a primitive batch for a renderer with no region work", renderer_.name()));
        arrived_[batch] = 1;
        draw_next(now);
        return;
    }
    if (signal_of(payload) == Signal::Resume) {  // a region step is done
        drawing_ = false;
        draw_next(now);
        return;
    }
    const auto gp = gp_of(payload);
    const auto block = static_cast<std::uint32_t>(value_of(payload));
    if (signal_of(payload) == Signal::Arrival &&
        value_of(payload) >= kRefreshFirst) {  // a GP's refresh: one setup, a reply a block
        const std::vector<std::uint32_t>& list = run_.refresh_lists[gp][renderer_.index()];
        const std::size_t first = kRefreshBatch - 1 - value_of(payload);
        const std::size_t end =
            std::min(list.size(), first + std::max<std::uint32_t>(1, run_.refresh_blocks_per_message));
        for (std::size_t i = first; i < end; ++i) {
            const Tick ready = renderer_.serve_fetch(now, units_of(list[i]), i == first);
            run_.machine.events().schedule(ready, *this, pack(Signal::Ready, gp, list[i]));
        }
        return;
    }
    if (signal_of(payload) == Signal::Arrival) {  // a request has arrived: queue it
        const Tick ready = renderer_.serve_fetch(now, units_of(block));
        run_.machine.events().schedule(ready, *this, pack(Signal::Ready, gp, block));
        return;
    }
    // The reply is read out: send it.
    const std::uint64_t bits = static_cast<std::uint64_t>(units_of(block)) * run_.phase.blocks->unit_bits();
    RingNetwork& ring = run_.machine.ring();
    ring.send(
        run_.machine.events(), now,
        RingMessage{MessageKind::FetchReply, station_, ring.position(StationKind::GraphicsProcessor, gp), bits, false},
        *run_.gps[gp], pack(Signal::Arrival, gp, block));
}

void FrameBufferAgent::handle_event(Tick now, std::uint64_t payload) {
    if ((payload & kReadout) != 0) {
        const std::size_t renderer = payload & ~kReadout;
        frame_buffer_.pixels_written += run_.phase.regions[renderer].readout_pixels;
        run_.readout_arrived(renderer, now);
        return;
    }
    const auto task = static_cast<std::uint32_t>(payload);
    frame_buffer_.pixels_written += run_.task(task).pixels;
    run_.pixels_arrived(task, now);
}

void HostAgent::handle_event(Tick now, std::uint64_t payload) {
    const auto gp = gp_of(payload);
    std::uint64_t task = kNoTask;
    if (next_task < run_.phase.tasks.size()) task = next_task++;
    RingNetwork& ring = run_.machine.ring();
    ring.send(run_.machine.events(), now,
              RingMessage{MessageKind::Command, run_.host_station, ring.position(StationKind::GraphicsProcessor, gp),
                          32, false},
              *run_.gps[gp], pack(Signal::Task, gp, task));
}

}  // namespace pp5::engine
