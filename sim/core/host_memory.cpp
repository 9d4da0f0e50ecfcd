#include "sim/core/host_memory.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <unistd.h>

namespace pp5 {

double host_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 16e9;
}

void check_fits_host_memory(const std::string& file, const std::string& field, double bytes, const std::string& what) {
    const double host = host_memory_bytes();
    if (bytes > 0.5 * host)
        throw InputError(file, field, fmt::format("{} needs {:.1f} GB of this computer's memory, which has {:.1f} GB", what, bytes / 1e9,
                                                  host / 1e9));
}

}  // namespace pp5
