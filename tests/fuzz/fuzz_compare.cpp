// Runs' statistics for `pp5sim compare`: read with the nesting limit, checked to be a run's stats.json,
// and compared with themselves and with an empty run.
#include "frontends/compare/stats_compare.h"
#include "sim/core/json_input.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("stats.json", data, size);
    return pp5::fuzz::refused_only_as_input([&] {
        const nlohmann::json stats = pp5::read_json_file(path, "compare", std::uintmax_t{1} << 30);
        pp5::check_run_stats(stats, path.string());
        (void)pp5::compare_stats(stats, stats, {});
        (void)pp5::compare_stats(stats, nlohmann::json::object(), {0.01, true});
    });
}
