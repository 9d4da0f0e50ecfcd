#include "kernels/api/kernel.h"

#include "sim/core/input_error.h"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace pp5 {

nlohmann::json KernelRun::run_stats() const { return nullptr; }

double Kernel::metric(const std::string& name, const KernelFrame&, const FrameTiming&) const {
    throw std::domain_error("kernel " + this->name() + " has no metric " + name);
}

double Kernel::formula(const std::string& name, const FormulaInputs&) const {
    throw std::domain_error("kernel " + this->name() + " has no formula " + name);
}

void refuse_stationary_lights(const Scenario& scenario, const std::string& kernel, const std::string& why) {
    if (has_stationary_lights(scenario))
        throw InputError(scenario.file.string(), "shading.stationary_lights",
                         "the " + kernel + " kernel cannot time stationary lights: " + why +
                             "; the levoy and yuan kernels shade them on the PPs");
}

}  // namespace pp5
