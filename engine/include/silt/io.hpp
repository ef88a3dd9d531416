// Outputs of a run: block-averaged statistics, the stats CSV, the summary JSON, checkpoints.
#pragma once

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "silt/simulation.hpp"

namespace silt {

// Mean and statistical error of the mean of a correlated series by block averaging
// (Flyvbjerg & Petersen 1989). Blocks of 2^k samples; the block size is the smallest B with
// B^3 > 2 n (s_B / s_1)^4 (Wolff 2004; Lee et al. 2011), s_B the naive error at block size B.
struct BlockAverage {
  double mean = 0;
  double err = 0;
  int64_t n = 0;
  int64_t block = 1;       // samples per block at the chosen level
  bool converged = false;  // false: too few samples for the correlation time (err is a lower bound)
};
BlockAverage block_average(const std::vector<double>& x);

// Time series of observables in memory, written to CSV as samples arrive.
class StatsWriter {
 public:
  // Opens `path` ("" = no file). Throws IoError.
  StatsWriter(const std::string& path, std::vector<std::string> names);
  ~StatsWriter();
  // One sample taken at simulated time t (kept whether or not "t" is among the names, so that
  // --average-from applies to any list of observables).
  void add(const std::vector<double>& row, double t);
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::vector<double>>& rows() const { return rows_; }
  const std::vector<double>& times() const { return times_; }
  void flush();

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> rows_;
  std::vector<double> times_;
};

// A profile sampled during a run (one value per bin and sample); the summary gives each bin's
// time average and its block-averaging error.
struct ProfileSeries {
  std::string name;        // e.g. "vx(y)"
  std::string coordinate;  // meaning of x, e.g. "y / L_y"
  std::vector<double> x;
  std::vector<std::vector<double>> samples;
};

struct SummaryInput {
  std::string scene;
  std::string status;  // ok | failed | interrupted | static
  int exit_code = 0;
  double wall_s = 0;
  int64_t steps_run = 0;
  double average_from = 0;
  std::vector<std::string> warnings;
  std::vector<ProfileSeries> profiles;
};
// Summary JSON of INTERFACE.md. Throws IoError.
void write_summary(const std::string& path, const SummaryInput& in, const Simulation& sim, const StatsWriter& stats);

// VTK XML output for ParaView and OVITO: DIR/grains_NNNNNN.vtu (points with radius, velocity,
// angular velocity, force, id, frozen), DIR/contacts_NNNNNN.vtp (one line per contact with its
// normal and tangential force) and DIR/index.pvd (the time series). Fluid fields (.vti) come with
// the fluid module.
class VtkWriter {
 public:
  explicit VtkWriter(std::string dir);  // creates dir; throws IoError
  void write(const Model& m, const State& s);
  int64_t count() const { return count_; }

 private:
  struct Entry {
    double t;
    std::string grains, contacts;
  };
  std::string dir_;
  int64_t count_ = 0;
  std::vector<Entry> entries_;
};

// Checkpoints: binary, versioned, with a checksum; written to a temporary file then renamed,
// so an interrupted write leaves the previous checkpoint intact.
void write_checkpoint(const std::string& path, const Model& m, const State& s);
// Throws IoError for unreadable, corrupt, foreign-scene or other-version files.
State read_checkpoint(const std::string& path, const Model& m);

}  // namespace silt
