// The benchmarks' main: Google Benchmark's own, after the allocator policy the CLI sets, so that a
// benchmark's frames cost the host what `pp5sim render` and `pp5sim serve` frames do.

#include "sim/core/host_memory.h"

#include <benchmark/benchmark.h>

int main(int argc, char** argv) {
    pp5::keep_freed_memory_for_reuse();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
