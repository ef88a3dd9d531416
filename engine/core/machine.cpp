#include "core/machine.hpp"

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

namespace silt {

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 1e18;
}

double available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("MemAvailable:", 0) == 0) {
      std::istringstream f(line.substr(13));
      double kib = 0;
      if (f >> kib) return kib * 1024.0;
    }
  return physical_memory_bytes();
}

}  // namespace silt
