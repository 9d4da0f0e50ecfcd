#pragma once
// What a graphics processor's machine-level work costs on the i860, in GP clock cycles: looking a block
// up in its cache, sending and receiving ring messages, switching between contexts. What a kernel's
// own operations cost is declared by the kernel ("gp_cost.<kernel>.*", in flops or cycles) and resolved
// with cost_of(). None of these numbers is published: each default is an operation count of the
// obvious implementation, documented with the parameter, and the calibration scales them. A cost is
// kept in picoseconds so that sums are exact.

#include "sim/core/config.h"
#include "sim/core/param.h"
#include "sim/core/time.h"

#include <cstdint>
#include <string>

namespace pp5 {

struct GpCostModel {
    Tick cache_lookup = 0;
    Tick message_send = 0;      // composing and handing a message to the ring interface
    Tick message_receive = 0;   // taking a message from the ring interface
    Tick receive_per_word = 0;  // copying one received word into the cache
    Tick context_switch = 0;    // saving one context's state and restoring another's

    static const ParamGroup& params();
    static GpCostModel from(const MachineConfig& config);

    // One operation's cost on this machine's GPs for the cost parameter `key` (any group's): a count of
    // flops at gp.sustained_mflops, or of cycles at gp.clock_mhz, as the parameter's unit says, times
    // the calibration scale of that family.
    static Tick cost_of(const MachineConfig& config, const std::string& key);
};

}  // namespace pp5
