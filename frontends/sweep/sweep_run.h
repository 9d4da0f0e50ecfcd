#pragma once
// Running a sweep: its points (every scenario at every grid combination, then the explicit points),
// the share of them one shard runs, and each point's per-frame metrics. Points that differ only in
// timing parameters share one recording of the scenario and are re-timed (calibration/timing_model.h),
// exactly as a fresh render would time them; a point that changes what is computed gets a recording
// of its own. A point that fails (a machine too small for the volume, say) keeps its error and the
// sweep goes on. Nothing here depends on the thread or shard count.

#include "frontends/sweep/sweep_spec.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

struct SweepPoint {
    std::size_t index = 0;
    std::string scenario;
    SweepAssignment parameters;  // what this point sets beyond the sweep's fixed overrides
};

// Scenario by scenario: the grid (first axis slowest), then the explicit points.
std::vector<SweepPoint> plan_sweep(const SweepSpec& spec);

// Every count-th point from index: shard K of N takes the points whose index is K mod N.
struct Shard {
    std::size_t index = 0;
    std::size_t count = 1;
    bool takes(std::size_t point) const { return point % count == index; }
};
// "K/N" with 0 <= K < N; throws InputError (--shard).
Shard parse_shard(const std::string& text);
// The shard a launcher gives through its environment: mpirun (Open MPI's OMPI_COMM_WORLD_RANK and
// _SIZE, or PMI_RANK and PMI_SIZE), or a Slurm array task (SLURM_ARRAY_TASK_ID less
// SLURM_ARRAY_TASK_MIN, of SLURM_ARRAY_TASK_COUNT). None when not launched so.
std::optional<Shard> shard_from_environment();

struct SweepColumn {
    std::string name;
    std::string unit;
    std::string description;
};

struct SweepFrameResult {
    std::size_t frame = 0;
    std::string label;
    std::vector<std::optional<double>> values;  // one per column; none where the frame has no such figure
};

struct SweepPointResult {
    SweepPoint point;
    std::string error;          // empty: the point ran
    nlohmann::json parameters;  // every resolved parameter's value, key -> value
    std::vector<SweepFrameResult> frames;
};

struct SweepResult {
    nlohmann::json header;  // the sweep as run: name, scenarios, machine, axes, total points, ...
    std::vector<SweepColumn> columns;
    std::vector<SweepPointResult> points;  // ascending index
    // What the bands cost this process (not written: it differs between shards).
    std::size_t uncertainty_retimings = 0;
    double uncertainty_seconds = 0.0;
};

using SweepProgress = std::function<void(std::size_t done, std::size_t total)>;

// Runs the points `shard` takes; progress is called (from one thread at a time) as points finish.
SweepResult run_sweep(const SweepSpec& spec, const Shard& shard, const SweepProgress& progress = {});

}  // namespace pp5
