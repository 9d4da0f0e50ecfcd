#include "sim/components/gp_cost_model.h"

#include "sim/core/calibration.h"

#include <cmath>
#include <stdexcept>

namespace pp5 {

const ParamGroup& GpCostModel::params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost", "Graphics-processor (i860) cost of the machine's own operations; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        const auto cycles = [&g](const char* name, double def, const char* doc, const char* count) {
            g.real(name, def, "cycles", 0, 1e7, doc, Provenance::Default, count).hand_counted();
        };
        cycles("cache_lookup_cycles", 10, "Look a block up in the GP's cache",
               "a hash, a set index and up to 8 tag compares");
        cycles("message_send_cycles", 50, "Compose a message and hand it to the ring interface",
               "a header and a few stores to the interface's registers");
        cycles("message_receive_cycles", 50, "Take a message from the ring interface",
               "the same, in the other direction");
        cycles("receive_cycles_per_word", 1, "Copy one received word into the cache", "a load and a store, pipelined");
        cycles("context_switch_cycles", 32, "Save a waiting context's state and restore a ready one's",
               "about 16 registers of ray state out and in");
        return g;
    }();
    return group;
}

Tick GpCostModel::cost_of(const MachineConfig& config, const std::string& key) {
    const ParamSpec* spec = config.find_spec(key);
    if (spec == nullptr) throw std::logic_error("GP cost: no parameter " + key);
    const CalibrationScales scales = CalibrationScales::from(config);
    double unit_ps = 0.0;
    if (spec->unit == "flops") unit_ps = scales.gp_flops * 1e12 / (config.real("gp.sustained_mflops") * 1e6);
    else if (spec->unit == "cycles") unit_ps = scales.gp_cycles * 1e12 / (config.real("gp.clock_mhz") * 1e6);
    else throw std::logic_error("GP cost: " + key + " is in " + spec->unit + ", not flops or cycles");
    return static_cast<Tick>(std::llround(config.real(key) * unit_ps));
}

GpCostModel GpCostModel::from(const MachineConfig& config) {
    const auto cycles = [&](const char* name) { return cost_of(config, std::string("gp_cost.") + name); };
    GpCostModel m;
    m.cache_lookup = cycles("cache_lookup_cycles");
    m.message_send = cycles("message_send_cycles");
    m.message_receive = cycles("message_receive_cycles");
    m.receive_per_word = cycles("receive_cycles_per_word");
    m.context_switch = cycles("context_switch_cycles");
    return m;
}

}  // namespace pp5
