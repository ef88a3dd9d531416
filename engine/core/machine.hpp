// What the machine offers: the memory a run may take.
#pragma once

#include <cstdint>

namespace silt {

// Bytes of memory available to a new allocation now (MemAvailable of /proc/meminfo; the physical
// memory where that is not known), or what is left of the address space when it is limited
// (ulimit -v), if that is less.
double available_memory_bytes();
// Bytes of physical memory (1e18 where that is not known).
double physical_memory_bytes();

}  // namespace silt
