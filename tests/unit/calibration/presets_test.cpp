// The Pixel-planes 5 preset restates every machine parameter's default, so that a reader of the file
// sees the whole machine. A kernel's parameters, the costs of its GP operations (gp_cost.<kernel>.*)
// included, are declared beside the kernel alone: adding a kernel touches no preset.

#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "sim/machine/machine.h"
#include "tests/support/source_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace pp5 {
namespace {

TEST(Presets, Pxpl5RestatesEveryMachineDefault) {
    MachineConfig preset(run_param_groups());
    preset.load_file(pp5::test::source_dir() / "sim/machines/pxpl5.toml");
    EXPECT_EQ(preset.machine_name(), "pxpl5");
    const nlohmann::json defaults = MachineConfig(run_param_groups()).to_json()["parameters"];
    const nlohmann::json loaded = preset.to_json()["parameters"];
    // Beyond the machine's own groups, every parameter is a kernel's (or the host reference renderer's
    // costs, which host-check prices it with): declared beside its code.
    const MachineConfig machine_only(Machine::param_groups());
    const auto is_kernels = [&](const std::string& key) { return machine_only.find_spec(key) == nullptr; };
    std::size_t checked = 0, kernels_own = 0;
    for (const auto& [key, entry] : defaults.items()) {
        EXPECT_EQ(loaded[key]["value"], entry["value"]) << key;
        if (is_kernels(key)) {
            EXPECT_EQ(loaded[key]["origin"], "default") << key << ": a kernel's default belongs beside its code";
            ++kernels_own;
            continue;
        }
        EXPECT_NE(loaded[key]["origin"], "default") << key << " is missing from pxpl5.toml";
        ++checked;
    }
    EXPECT_GT(checked, 50u);
    EXPECT_GT(kernels_own, 40u);  // every kernel's settings and costs
}

}  // namespace
}  // namespace pp5
