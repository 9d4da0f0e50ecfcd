// OBJ meshes placed by a scenario's [[meshes]]: the mesh reader's vertices, faces and indices (huge,
// negative, past the end, non-finite coordinates) as the scenario loader checks them.
#include "scene/scenario/scenario.h"
#include "tests/fuzz/fuzz_input.h"

namespace {

constexpr const char* kScenario = R"(
[scenario]
name = "fuzz-mesh"
[dataset]
phantom = "sphere"
size = 16
[classification]
kind = "piecewise-linear"
points = [{ value = 50.0, opacity = 0.0 }, { value = 150.0, opacity = 0.8 }]
[image]
width = 16
height = 16
[[meshes]]
file = "mesh.obj"
scale = [4.0, 4.0, 4.0]
translate = [8.0, 8.0, 8.0]
color = [0.6, 0.2, 0.8]
opacity = 0.9
)";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    pp5::fuzz::write_scratch("mesh.obj", data, size);
    const auto scenario_path = pp5::fuzz::scratch_directory() / "fuzz-mesh.toml";
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_scenario_text(kScenario, scenario_path); });
}
