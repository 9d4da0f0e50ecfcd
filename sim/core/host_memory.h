#pragma once
// This computer's memory, and the one test every allocation an input decides makes first: whether it
// fits in half of it. Beyond that a run is refused up front, saying how much it would need, instead of
// allocating until the system kills it (the other half is for what the run computes besides).

#include <string>

namespace pp5 {

double host_memory_bytes();

// Throws InputError(file, field, "<what> needs N GB ...") when `bytes` exceed half of host_memory_bytes().
void check_fits_host_memory(const std::string& file, const std::string& field, double bytes, const std::string& what);

}  // namespace pp5
