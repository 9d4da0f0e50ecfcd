#include "frontends/lecture_pictures.h"

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <variant>

namespace pp5 {

namespace {

// Well-separated hues for any number of GPs: the golden angle around the colour wheel.
glm::vec3 gp_colour(std::uint32_t gp) {
    const float hue = std::fmod(static_cast<float>(gp) * 0.61803398875f, 1.0f) * 6.0f;
    const float x = 1.0f - std::abs(std::fmod(hue, 2.0f) - 1.0f);
    const int sector = static_cast<int>(hue);
    const glm::vec3 rgb = sector == 0   ? glm::vec3(1, x, 0)
                          : sector == 1 ? glm::vec3(x, 1, 0)
                          : sector == 2 ? glm::vec3(0, 1, x)
                          : sector == 3 ? glm::vec3(0, x, 1)
                          : sector == 4 ? glm::vec3(x, 0, 1)
                                        : glm::vec3(1, 0, x);
    return 0.25f + 0.75f * rgb;
}

// A pixel's luminance, clamped to [0, 1]: the picture shows through the map's tint.
float brightness(const glm::vec4& p) { return glm::clamp(0.3f * p.r + 0.59f * p.g + 0.11f * p.b, 0.0f, 1.0f); }

}  // namespace

Image passes_strip(const std::vector<Image>& passes) {
    if (passes.empty()) throw std::invalid_argument("passes_strip: no passes");
    constexpr int kGap = 4;
    const int w = passes.front().width, h = passes.front().height;
    const int count = static_cast<int>(passes.size());
    Image strip(count * w + (count - 1) * kGap, h);
    std::fill(strip.pixels.begin(), strip.pixels.end(), glm::vec4(1.0f));
    for (int p = 0; p < count; ++p) {
        const Image& pass = passes[static_cast<std::size_t>(p)];
        if (pass.width != w || pass.height != h) throw std::invalid_argument("passes_strip: the passes differ in size");
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) strip.at(p * (w + kGap) + x, y) = pass.at(x, y);
    }
    return strip;
}

std::optional<Image> gp_tile_map(const FrameWork& work, const FrameTiming& timing, std::size_t gp_count,
                                 const Image& frame, const std::string& phase_name) {
    const GpPhase* phase = nullptr;
    for (const Phase& p : work.phases)
        if (p.name == phase_name) phase = std::get_if<GpPhase>(&p.work);
    const PhaseTiming* timed = timing.phase(phase_name);
    if (phase == nullptr || timed == nullptr || timed->task_gp.size() != phase->tasks.size()) return std::nullopt;

    // Per tile (by its corner), the GP that cast most of its rays.
    struct Tile {
        ScreenRect rect;
        std::map<std::uint32_t, std::uint64_t> items_by_gp;
    };
    std::map<std::pair<int, int>, Tile> tiles;
    for (std::size_t t = 0; t < phase->tasks.size(); ++t) {
        const GpTask& task = phase->tasks[t];
        if (task.screen.width == 0 || timed->task_gp[t] >= gp_count) continue;
        Tile& tile = tiles[{task.screen.x, task.screen.y}];
        tile.rect = task.screen;
        tile.items_by_gp[timed->task_gp[t]] += std::max<std::uint32_t>(task.item_count, 1);
    }
    if (tiles.empty()) return std::nullopt;

    Image map(frame.width, frame.height);
    for (std::size_t i = 0; i < map.pixels.size(); ++i)
        map.pixels[i] =
            glm::vec4(glm::vec3(0.15f + 0.35f * brightness(frame.pixels[i])), 1.0f);  // untouched tiles stay grey
    for (const auto& [corner, tile] : tiles) {
        const auto busiest = std::max_element(tile.items_by_gp.begin(), tile.items_by_gp.end(),
                                              [](const auto& a, const auto& b) { return a.second < b.second; });
        const glm::vec3 colour = gp_colour(busiest->first);
        for (int y = tile.rect.y; y < std::min<int>(frame.height, tile.rect.y + tile.rect.height); ++y)
            for (int x = tile.rect.x; x < std::min<int>(frame.width, tile.rect.x + tile.rect.width); ++x) {
                const bool edge = x == tile.rect.x || y == tile.rect.y;
                map.at(x, y) =
                    glm::vec4(edge ? 0.5f * colour : colour * (0.45f + 0.55f * brightness(frame.at(x, y))), 1.0f);
            }
    }
    return map;
}

PlotSpec utilisation_over_time(const TraceRecorder& trace, Tick start, Tick end,
                               const std::map<std::string, std::size_t>& counts, int bins) {
    if (end <= start || bins < 1) throw std::invalid_argument("utilisation_over_time: an empty span of time");
    const double width = static_cast<double>(end - start) / bins;
    PlotSpec spec;
    spec.title = "utilisation over the frame";
    spec.x_label = "simulated milliseconds from the frame's start";
    spec.y_label = "busy fraction";
    spec.extra_commands = {"set yrange [0:1.05]", "set key outside right"};
    for (const auto& [group, count] : counts) {
        const auto spans = trace.busy_spans().find(group);
        if (count == 0 || spans == trace.busy_spans().end()) continue;
        std::vector<double> busy(static_cast<std::size_t>(bins), 0.0);
        for (const auto& [from, to] : spans->second) {
            const Tick a = std::max(from, start), b = std::min(to, end);
            if (b <= a) continue;
            const int first = static_cast<int>(static_cast<double>(a - start) / width);
            const int last = std::min(bins - 1, static_cast<int>(static_cast<double>(b - start) / width));
            for (int i = first; i <= last; ++i) {
                const double lo = static_cast<double>(start) + i * width, hi = lo + width;
                busy[static_cast<std::size_t>(i)] +=
                    std::max(0.0, std::min(hi, static_cast<double>(b)) - std::max(lo, static_cast<double>(a)));
            }
        }
        PlotSeries series;
        series.title = group;
        series.style = "steps lw 2";
        for (int i = 0; i < bins; ++i) {
            series.x.push_back(ticks_to_seconds(static_cast<Tick>(i * width)) * 1e3);
            series.y.push_back(busy[static_cast<std::size_t>(i)] / (width * static_cast<double>(count)));
        }
        spec.series.push_back(std::move(series));
    }
    return spec;
}

FrameTimeline frame_timeline(const TraceRecorder& trace, const FrameTiming& timing,
                             const std::vector<std::pair<std::string, std::string>>& components, int bins) {
    if (bins < 1) throw std::invalid_argument("frame_timeline: bins must be positive");
    FrameTimeline out;
    out.start_ps = timing.start_ps;
    out.end_ps = timing.end_ps;
    out.bins = bins;
    out.activities = trace.slice_names();
    out.slices_dropped = trace.slices_dropped();
    const auto rank = [](const std::string& group) {
        static const std::vector<std::string> order{"GPs", "renderers", "ring"};
        return std::find(order.begin(), order.end(), group) - order.begin();
    };
    std::vector<std::pair<std::string, std::string>> wanted = components;
    std::stable_sort(wanted.begin(), wanted.end(),
                     [&](const auto& a, const auto& b) { return rank(a.first) < rank(b.first); });
    std::map<std::pair<std::string, std::string>, int> track_of;
    for (const TraceRecorder::Track& t : trace.tracks()) track_of[{t.group, t.name}] = t.id;
    std::map<int, std::size_t> lane_of;
    for (const auto& [group, name] : wanted) {
        if (const auto t = track_of.find({group, name}); t != track_of.end()) lane_of[t->second] = out.lanes.size();
        out.lanes.push_back({group, name, std::vector<float>(static_cast<std::size_t>(bins)),
                             std::vector<int>(static_cast<std::size_t>(bins), -1)});
    }
    const Tick span = timing.end_ps - timing.start_ps;
    if (span <= 0) return out;

    // Busy time per lane, bin and activity, then each bin's share and its leading activity.
    const std::size_t kinds = out.activities.size();
    const auto waiting = std::find(out.activities.begin(), out.activities.end(), "waiting") - out.activities.begin();
    std::vector<double> time(out.lanes.size() * static_cast<std::size_t>(bins) * kinds, 0.0);
    const double bin_ps = static_cast<double>(span) / bins;
    for (const TraceRecorder::Slice& s : trace.slices()) {
        const auto lane = lane_of.find(s.track);
        if (lane == lane_of.end() || s.what == waiting) continue;
        const double from = static_cast<double>(std::max(s.start, timing.start_ps) - timing.start_ps);
        const double to = static_cast<double>(std::min(s.end, timing.end_ps) - timing.start_ps);
        if (to <= from) continue;
        const int first = std::min(bins - 1, static_cast<int>(from / bin_ps)),
                  last = std::min(bins - 1, static_cast<int>(to / bin_ps));
        for (int b = first; b <= last; ++b) {
            const double overlap = std::min(to, (b + 1) * bin_ps) - std::max(from, b * bin_ps);
            if (overlap > 0)
                time[(lane->second * static_cast<std::size_t>(bins) + static_cast<std::size_t>(b)) * kinds +
                     static_cast<std::size_t>(s.what)] += overlap;
        }
    }
    std::map<std::string, bool> group_did_something;
    for (std::size_t l = 0; l < out.lanes.size(); ++l)
        for (std::size_t b = 0; b < static_cast<std::size_t>(bins); ++b) {
            const double* by_kind = &time[(l * static_cast<std::size_t>(bins) + b) * kinds];
            const auto leading = std::max_element(by_kind, by_kind + kinds);
            double busy = 0.0;
            for (std::size_t k = 0; k < kinds; ++k) busy += by_kind[k];
            if (busy <= 0.0) continue;
            // A component does one thing at a time, but slices of one track can overlap at their ends.
            out.lanes[l].busy[b] = static_cast<float>(std::min(1.0, busy / bin_ps));
            out.lanes[l].what[b] = static_cast<int>(leading - by_kind);
            group_did_something[out.lanes[l].group] = true;
        }
    // A kind of component the frame recorded nothing for (the host and the frame buffer only send
    // and receive messages, which the ring's lanes show) has no lanes.
    std::erase_if(out.lanes, [&](const TimelineLane& lane) { return !group_did_something[lane.group]; });
    return out;
}

}  // namespace pp5
