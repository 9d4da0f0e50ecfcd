#include "kernels/interface/kernel.h"

#include <stdexcept>

namespace pp5 {

double Kernel::metric(const std::string& name, const KernelFrame&, const FrameTiming&) const {
    throw std::domain_error("kernel " + this->name() + " has no metric " + name);
}

double Kernel::formula(const std::string& name, const FormulaInputs&) const {
    throw std::domain_error("kernel " + this->name() + " has no formula " + name);
}

}  // namespace pp5
