// Scenario files: TOML syntax, nesting and every field's type, range and combination, as `render`
// reads them (the dataset a scenario names is not loaded: the volume harnesses cover the loaders).
#include "scene/scenario/scenario.h"
#include "tests/fuzz/fuzz_input.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const auto path = pp5::fuzz::scratch_directory() / "fuzz.toml";
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_scenario_text(text, path); });
}
