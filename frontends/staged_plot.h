#pragma once
// A plot staged with a run's other outputs: NAME.dat and NAME.gp always, NAME.png when gnuplot drew
// it. A missing or failing gnuplot costs the picture, never the run or the work behind the plot.

#include "frontends/plot.h"
#include "frontends/staged_output.h"

#include <optional>
#include <string>

namespace pp5 {

// Returns a one-line warning for the user when the picture could not be drawn.
std::optional<std::string> stage_plot(StagedOutput& output, const PlotSpec& spec, const std::string& name);

}  // namespace pp5
