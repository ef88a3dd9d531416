// Small helpers shared by the benchmark programs: timing, machine description, CSV append.
#pragma once

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace silt::bench {

// The body of a benchmark's main: a scene error, a bad option value or a failure reading a file
// ends the program with its message and exit code 2 instead of an abort.
template <class F>
int guarded_main(F&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}

// The median of v (the mean of the middle two for an even count).
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline std::string today() {
  char buf[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

inline std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

inline std::string host() {
  char buf[256] = {0};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

// Peak resident memory of this process [bytes].
inline double peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;
}

// Append one row to a CSV file, writing the header first when the file is new. When a benchmark
// gains columns at the end, the file's header is extended and its older rows get empty fields.
inline void append_csv(const std::string& path, const std::string& header, const std::string& row) {
  std::ifstream in(path);
  std::string first;
  if (in && std::getline(in, first) && first != header) {
    if (header.rfind(first + ",", 0) != 0)
      throw std::runtime_error(path + ": its header is not this benchmark's; move the file away");
    const auto extra = std::count(header.begin() + first.size(), header.end(), ',');
    std::string text = header + "\n", line;
    while (std::getline(in, line)) text += line + std::string(extra, ',') + "\n";
    in.close();
    std::ofstream(path, std::ios::trunc) << text;
  }
  const bool fresh = first.empty();
  std::ofstream out(path, std::ios::app);
  if (fresh) out << header << "\n";
  out << row << "\n";
}

// A comma-separated list of numbers ("1e-3,1e-4"); std::invalid_argument on a bad item.
inline std::vector<double> parse_list(const std::string& text) {
  std::vector<double> v;
  size_t at = 0;
  while (at <= text.size()) {
    const size_t end = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, end - at);
    size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size())
      throw std::invalid_argument("not a number in the list '" + text + "': '" + item + "'");
    v.push_back(x);
    at = end + 1;
  }
  return v;
}

// An --only value that names none of a program's sections: refused, with their names (it ran
// nothing and said so by silence).
inline void check_only(const std::string& only, const std::vector<std::string>& names) {
  if (only.empty() || std::find(names.begin(), names.end(), only) != names.end()) return;
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("--only " + only + ": no such section (" + list + ")");
}

// Run a shell command, returning its standard output.
inline std::string capture(const std::string& cmd) {
  std::string out;
  std::FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

// The command that starts Debian's LAMMPS on one process, or on `ranks` MPI ranks.
inline std::string lammps_launch(int ranks) {
  return ranks > 1 ? "mpirun --allow-run-as-root -np " + std::to_string(ranks) + " lmp" : "lmp";
}

}  // namespace silt::bench
