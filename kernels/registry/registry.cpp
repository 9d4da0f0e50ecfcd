#include "kernels/registry/registry.h"

#include "kernels/levoy/levoy_kernel.h"
#include "kernels/perm/perm_kernel.h"
#include "kernels/reference_kernel/reference_kernel.h"
#include "kernels/wilson/wilson_kernel.h"
#include "kernels/yuan/yuan_kernel.h"
#include "sim/core/input_error.h"

#include <stdexcept>

namespace pp5 {

namespace {
std::vector<const Kernel*>& registry() {
    static std::vector<const Kernel*> all = {
        &levoy_kernel(),      // Levoy 1989: the volume rendering workstation on Pixel-planes 5
        &yuan_kernel(),       // Yuan et al. 2003: hybrid point/splat splatting over the renderers' screen regions
        &wilson_kernel(),     // Wilson et al. 2002: a low-resolution volume's slices plus points where it errs
        &perm_kernel(),       // Lim and Shin: rays through precomputed, quantized density and gradient per cell
        &reference_kernel(),  // the host's floating-point renderer, no machine
    };
    return all;
}
}  // namespace

const std::vector<const Kernel*>& kernels() { return registry(); }

const Kernel* find_kernel(const std::string& name) {
    for (const Kernel* k : registry())
        if (k->name() == name) return k;
    return nullptr;
}

std::string kernel_names() {
    std::string known;
    for (const Kernel* k : registry()) known += (known.empty() ? "" : ", ") + k->name();
    return known;
}

const Kernel& kernel_for(const Scenario& scenario) {
    if (const Kernel* k = find_kernel(scenario.kernel)) return *k;
    throw InputError(scenario.file.string(), "scenario.kernel",
                     "unknown kernel \"" + scenario.kernel + "\"; the known ones are " + kernel_names());
}

namespace {

// `"levoy"` or `"levoy" or "yuan"`: the kernels on the machine with a feature.
std::string kernels_with(bool KernelFeatures::*feature) {
    std::string names;
    for (const Kernel* k : registry())
        if (k->runs_on_machine() && k->features().*feature)
            names += (names.empty() ? "\"" : " or \"") + k->name() + "\"";
    return names;
}

void refuse_missing(const Kernel& kernel, const Scenario& scenario, bool KernelFeatures::*feature, const char* field,
                    const char* what) {
    std::string why = "the " + kernel.name() + " kernel " + what;
    if (const std::string others = kernels_with(feature); !others.empty()) why += "; use kernel = " + others;
    throw InputError(scenario.file.string(), field, why);
}

}  // namespace

void check_scenario(const Kernel& kernel, const Scenario& scenario) {
    kernel.check(scenario);
    const KernelFeatures has = kernel.features();
    if (!has.polygons && !scenario.polygons.empty())
        refuse_missing(kernel, scenario, &KernelFeatures::polygons, "polygons", "does not scan-convert polygons");
    if (!has.regions)
        for (const FrameSpec& frame : scenario.frames)
            if (frame.region)
                refuse_missing(kernel, scenario, &KernelFeatures::regions, "region", "has no volume-of-interest tool");
}

void register_kernel(const Kernel& kernel) {
    if (find_kernel(kernel.name()) != nullptr) throw std::logic_error("kernel registered twice: " + kernel.name());
    registry().push_back(&kernel);
}

}  // namespace pp5
