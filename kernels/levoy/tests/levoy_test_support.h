#pragma once
// Helpers shared by the levoy kernel's tests: a configuration holding the machine's and the kernel's
// parameters, small by default so that tests run in milliseconds.

#include "kernels/levoy/levoy_costs.h"
#include "kernels/levoy/levoy_settings.h"
#include "sim/machine/machine.h"

#include <initializer_list>
#include <string_view>

namespace pp5::test {

// The default machine and levoy settings, then `base` and `overrides` applied in order.
inline MachineConfig levoy_config(std::initializer_list<std::string_view> base,
                                  std::initializer_list<std::string_view> overrides) {
    std::vector<const ParamGroup*> groups = Machine::param_groups();
    groups.push_back(&VoxelStoreSettings::placement_params());
    groups.push_back(&VoxelStoreSettings::layout_params());
    groups.push_back(&LevoySettings::params());
    groups.push_back(&levoy_cost_params());
    MachineConfig config(groups);
    for (auto o : base) config.apply_override(o);
    for (auto o : overrides) config.apply_override(o);
    return config;
}

}  // namespace pp5::test
