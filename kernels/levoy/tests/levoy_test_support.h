#pragma once
// Helpers shared by the levoy kernel's tests: a configuration holding the machine's and the kernel's
// parameters, small by default so that tests run in milliseconds.

#include "kernels/levoy/levoy_kernel.h"
#include "sim/machine/machine.h"

#include <initializer_list>
#include <string_view>

namespace pp5::test {

// The default machine and every levoy parameter, then `base` and `overrides` applied in order.
inline MachineConfig levoy_config(std::initializer_list<std::string_view> base,
                                  std::initializer_list<std::string_view> overrides) {
    std::vector<const ParamGroup*> groups = Machine::param_groups();
    for (const ParamGroup* group : levoy_kernel().param_groups()) groups.push_back(group);
    MachineConfig config(groups);
    for (auto o : base) config.apply_override(o);
    for (auto o : overrides) config.apply_override(o);
    return config;
}

}  // namespace pp5::test
