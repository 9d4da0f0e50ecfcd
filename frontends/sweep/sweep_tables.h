#pragma once
// A sweep's results as files: sweep.json (the sweep as run, the columns with units, every point's
// resolved parameters and per-frame metrics or its error), sweep.csv (one row per point and frame:
// parameters, status, then every metric with its unit in the header), a shard's share of them, the
// merge of every shard into what one process would have written, and the plots.

#include "frontends/plot.h"
#include "frontends/sweep/sweep_run.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pp5 {

// The JSON of a whole sweep, or of one shard's points (with the shard recorded).
nlohmann::json sweep_to_json(const SweepResult& result, std::optional<Shard> shard = std::nullopt);
// Reads sweep_to_json's output back; throws InputError naming `file` and the field when it is not one.
SweepResult sweep_from_json(const nlohmann::json& json, const std::string& file);

std::string sweep_to_csv(const SweepResult& result);

// The name a shard's file takes: shard-K-of-N.json.
std::string shard_file_name(const Shard& shard);
// Joins every shard of one sweep (file name, contents) into the whole sweep. Throws InputError when
// they are not all the shards of one sweep: a shard missing or given twice, or headers that differ.
SweepResult merge_sweep_shards(const std::vector<std::pair<std::string, nlohmann::json>>& shards);

// One plot per scenario: the plot metric (the sweep's plot_metric, else the scenario kernel's first
// metric), averaged over the frames, against the plot axis (plot_x, else the first), one line per
// combination of the other axes. Named sweep_<scenario>; empty when nothing varies.
std::vector<std::pair<std::string, PlotSpec>> sweep_plots(const SweepResult& result);

}  // namespace pp5
