#include "kernels/registry/run_config.h"

#include "kernels/registry/registry.h"
#include "scene/reference/reference_costs.h"
#include "sim/machine/machine.h"

#include <algorithm>

namespace pp5 {

std::vector<const ParamGroup*> run_param_groups() {
    std::vector<const ParamGroup*> groups = Machine::param_groups();
    // Kernels that share a building block (the PP voxel store) list its group each; it is declared once.
    for (const Kernel* kernel : kernels())
        for (const ParamGroup* group : kernel->param_groups())
            if (std::find(groups.begin(), groups.end(), group) == groups.end()) groups.push_back(group);
    // What the host reference renderer's loop costs a processor: no kernel's frames use it, `pp5sim
    // host-check` prices the reference's runs with it.
    groups.push_back(&reference_cost_params());
    return groups;
}

MachineConfig load_run_config(const std::string& machine, const std::vector<std::string>& overrides) {
    MachineConfig config(run_param_groups());
    config.load_file(resolve_machine_file(machine));
    for (const auto& assignment : overrides) config.apply_override(assignment);
    return config;
}

}  // namespace pp5
