#pragma once
// The configuration of a run: every machine parameter plus the parameters of every registered kernel
// (its own "<kernel>.*" and the machine's costs of its operations), read from a machine file with
// --set overrides.

#include "sim/core/config.h"

#include <string>
#include <vector>

namespace pp5 {

std::vector<const ParamGroup*> run_param_groups();

// Defaults, then the machine file (a path or a preset name), then each "key=value" override.
MachineConfig load_run_config(const std::string& machine, const std::vector<std::string>& overrides);

}  // namespace pp5
