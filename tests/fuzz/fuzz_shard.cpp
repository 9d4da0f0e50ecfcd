// Sweep shards and sweep.json: a file copied back from a batch node, read as `pp5sim sweep --merge`
// reads it (nesting limit, whole shape), merged as a sweep of one shard, and written out again as the
// merge writes it (JSON, CSV, plots' series).
#include "frontends/sweep/sweep_tables.h"
#include "sim/core/json_input.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("shard-0-of-1.json", data, size);
    return pp5::fuzz::refused_only_as_input([&] {
        const nlohmann::json shard = pp5::read_json_file(path, "shard", std::uintmax_t{1} << 30);
        const pp5::SweepResult merged = pp5::merge_sweep_shards({{path.string(), shard}});
        (void)pp5::sweep_to_json(merged).dump();
        (void)pp5::sweep_to_csv(merged);
        (void)pp5::sweep_plots(merged);
    });
}
