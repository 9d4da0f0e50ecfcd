#pragma once
// The kernels pp5sim knows, one line each in registry.cpp (an explicit list: self-registering statics
// in static libraries are dropped by the linker). Frontends and calibration reach kernels only here.

#include "kernels/api/kernel.h"

#include <string>
#include <vector>

namespace pp5 {

// Every kernel, in the order `pp5sim params` and error messages list them.
const std::vector<const Kernel*>& kernels();
// The kernel of that name, or nullptr.
const Kernel* find_kernel(const std::string& name);
// "levoy, yuan, ...": the known kernels' names, for messages refusing an unknown one.
std::string kernel_names();
// The scenario's kernel; an unknown name is an InputError naming the scenario file and listing the
// known kernels.
const Kernel& kernel_for(const Scenario& scenario);

// The scenario as `kernel` would render it, checked: what the kernel itself refuses (Kernel::check),
// then each feature asked for that it lacks (Kernel::features), refused naming the kernels on the
// machine that have it. Throws InputError naming the scenario's file and field.
void check_scenario(const Kernel& kernel, const Scenario& scenario);

// Adds a kernel for the rest of the process (a test's own kernel); its name must be new.
void register_kernel(const Kernel& kernel);

}  // namespace pp5
