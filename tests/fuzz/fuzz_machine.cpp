// The machine of the fuzz targets: defines what engine/core/machine.cpp does (which the linker
// then leaves out of the static engine library), with the memory the target sets.
#include "core/machine.hpp"
#include "fuzz_support.hpp"

namespace {
double g_available = 1 << 30;
}

namespace silt {
double available_memory_bytes() { return g_available; }
double physical_memory_bytes() { return g_available; }
}  // namespace silt

namespace silt::fuzz {
void set_available_memory(double bytes) { g_available = bytes; }
}  // namespace silt::fuzz
