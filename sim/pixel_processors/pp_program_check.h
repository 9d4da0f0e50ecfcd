#pragma once
// What PpArray checks of a program and a slot context before any PP changes, so that a bad program
// leaves the array as it was.

#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_program.h"

namespace pp5 {

// Throws std::invalid_argument naming the program and the instruction when the program needs more
// local memory than the PPs have, more QEE expressions than the context gives, a record past the
// backing store's end, or refers to a field, table or expression it lacks (or shifts too far).
void check_runnable(const PpProgram& program, const PpSlotContext& context, int local_memory_bits,
                    int backing_store_bits);

}  // namespace pp5
