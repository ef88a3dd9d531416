#include "core/machine.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

namespace silt {
namespace {

// A number of kB from the line of /proc/<file> that starts with `key`, or -1.
double kib_from(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      std::istringstream f(line.substr(key.size()));
      double kib = 0;
      if (f >> kib) return kib;
    }
  return -1;
}

}  // namespace

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 1e18;
}

double available_memory_bytes() {
  double bytes = kib_from("/proc/meminfo", "MemAvailable:") * 1024.0;
  if (bytes < 0) bytes = physical_memory_bytes();
  // A limit on the address space (ulimit -v) binds first: what is left of it.
  rlimit lim{};
  if (getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    const double used = std::max(0.0, kib_from("/proc/self/status", "VmSize:") * 1024.0);
    bytes = std::min(bytes, std::max(0.0, static_cast<double>(lim.rlim_cur) - used));
  }
  return bytes;
}

}  // namespace silt
