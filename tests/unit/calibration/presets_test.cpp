// The Pixel-planes 5 preset restates every machine parameter's default, the costs of every kernel's
// GP operations included (gp_cost.<kernel>.*), so that a reader of the file sees the whole machine.

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
    // A kernel's own settings (every group it declares but its gp_cost.* costs) belong to runs, not machines.
    std::vector<std::string> run_settings;
    for (const Kernel* kernel : kernels())
        for (const ParamGroup* group : kernel->param_groups())
            if (!group->prefix().starts_with("gp_cost")) run_settings.push_back(group->prefix() + ".");
    const auto is_run_setting = [&](const std::string& key) {
        return std::any_of(run_settings.begin(), run_settings.end(),
                           [&](const std::string& p) { return key.starts_with(p); });
    };
    std::size_t checked = 0;
    for (const auto& [key, entry] : defaults.items()) {
        if (is_run_setting(key)) continue;
        EXPECT_EQ(loaded[key]["value"], entry["value"]) << key;
        EXPECT_NE(loaded[key]["origin"], "default") << key << " is missing from pxpl5.toml";
        ++checked;
    }
    EXPECT_GT(checked, 50u);
}

}  // namespace
}  // namespace pp5
