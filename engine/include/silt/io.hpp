// Outputs of a run: block-averaged statistics, the stats CSV, the summary JSON, checkpoints.
#pragma once

#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "silt/grid_field.hpp"
#include "silt/simulation.hpp"
#include "silt/statistics.hpp"

namespace silt {

// Time series of observables, written to CSV as samples arrive and kept for their means and
// errors: every sample in memory (the shell: `stats since T` chooses T later), or, streamed,
// only the block averages of the samples with t >= a time given up front (a batch run: its
// memory does not grow with its length).
class StatsWriter {
 public:
  // Opens `path` ("" = no file). Throws IoError. With `stream_from`, keeps no rows: only the
  // block averages of the samples with t >= *stream_from.
  StatsWriter(const std::string& path, std::vector<std::string> names,
              std::optional<double> stream_from = std::nullopt);
  ~StatsWriter();
  StatsWriter(StatsWriter&& other) noexcept;
  StatsWriter& operator=(StatsWriter&& other) noexcept;
  StatsWriter(const StatsWriter&) = delete;
  StatsWriter& operator=(const StatsWriter&) = delete;
  // One sample of the state at step `step`, simulated time t (kept whether or not "t" is among
  // the names, so that --average-from applies to any list of observables). The file is flushed
  // at every row (`tail -f` follows it; a killed run keeps its rows); a write error is kept for
  // flush() to report.
  void add(const std::vector<double>& row, double t, int64_t step = -1);
  // The step of the last sample, -1 when none.
  int64_t last_step() const { return last_step_; }
  const std::vector<std::string>& names() const { return names_; }
  // The samples kept (none when streamed).
  const std::vector<std::vector<double>>& rows() const { return rows_; }
  const std::vector<double>& times() const { return times_; }
  // Samples added so far, and the last one (empty before the first).
  int64_t samples() const { return samples_; }
  const std::vector<double>& last_row() const { return rows_.empty() ? last_row_ : rows_.back(); }
  // Mean and error of observable k over the samples with t >= since (streamed: the time given to
  // the constructor, or std::logic_error).
  BlockAverage average(size_t k, double since) const;
  // A state restored to time t at step `step`: the kept samples after t belong to a branch no
  // longer run and go (the file keeps its rows); the next sample of that step is not taken twice.
  // Returns how many went.
  size_t drop_after(double t, int64_t step);
  void flush();
  // The error that stopped the writes to the file ("" while all is well); add() keeps the rows.
  const std::string& error() const { return error_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> rows_;
  std::vector<double> times_;
  std::optional<double> stream_from_;
  std::vector<BlockAccumulator> streamed_;
  std::vector<double> last_row_;  // streamed: the last sample
  int64_t samples_ = 0;
  int64_t last_step_ = -1;
  std::string error_;
};

// A profile sampled during a run (one value per bin and sample); the summary gives each bin's
// time average and its block-averaging error (streamed: its memory does not grow with the run).
struct ProfileSeries {
  std::string name;        // e.g. "vx(y)"
  std::string coordinate;  // meaning of x, e.g. "y / L_y"
  std::vector<double> x;
  std::vector<BlockAccumulator> bins;
  int64_t samples = 0;
  // A sample of every bin; a bin with no grain in it (count 0) has no value in it, and is left
  // out (a slab above a chute's surface read as a measured 0 +- 0).
  void add(const std::vector<double>& values, const std::vector<int64_t>& counts) {
    if (bins.size() < values.size()) bins.resize(values.size());
    for (size_t k = 0; k < values.size(); ++k)
      if (k >= counts.size() || counts[k] > 0) bins[k].add(values[k]);
    ++samples;
  }
};

// Before a run: whether `path` can be written (its directory exists and is writable, or the file
// is); IoError saying why not, `what` naming the file ("summary", "checkpoint"). With
// `regular_only`, an existing path must be a regular file (a checkpoint is renamed over it: never
// over a device).
void check_output_path(const std::string& path, const std::string& what, bool regular_only = false);
// The file `path` names as one path: absolute, normal, symbolic links resolved as far as the path
// exists, no trailing slash; two names of one file give the same.
std::filesystem::path canonical_path(const std::string& path);
// Whether writing the output `path` would overwrite the file `file`: it is that file (by any
// name). A device or a pipe (written in place) overwrites nothing.
bool overwrites(const std::string& path, const std::string& file);
// Why two outputs would leave only one: "the same file"; "" when they are apart (or either is "",
// a device or a pipe).
std::string output_clash(const std::string& a, const std::string& b);
// A new temporary file beside `path`, to write it whole and rename it onto `path`: PATH.tmp.XXXXXX
// made by mkstemp, with the permissions open() gives (0666 less the umask). No other file is ever
// opened, emptied or replaced: a fixed PATH.tmp emptied a file of that name, a directory of that
// name failed every save at the end of its run, and two runs saving to one path failed each
// other's rename. fd < 0 (errno set) when none can be made.
struct TempFile {
  int fd = -1;
  std::string name;
};
TempFile make_temp_beside(const std::string& path);
// The first two of these outputs (option or name, path) that would overwrite each other, or one
// that is a VTK file's name in the VTK directory `vtk`: "--stats and --save name the same file,
// x", "" when none does.
std::string clashing_outputs(const std::vector<std::pair<std::string, std::string>>& outputs, const std::string& vtk);
// IoError when `path` is the input file `input` (the same file by another name too): an output
// given the scene's own name would overwrite it. `input_what` names the input in the message.
void check_not_input(const std::string& path, const std::string& input, const std::string& what,
                     const std::string& input_what = "the scene file");
// Before a run: the directory `dir` of a series of files (frames, VTK), made if it is not there;
// IoError when it cannot be, is not a directory, or cannot be written in, `what` naming the
// files ("frame", "VTK").
void make_output_directory(const std::string& dir, const std::string& what);
// Series of numbered files: (PREFIX, EXT) for the names PREFIX + six digits + EXT.
using NumberedSeries = std::vector<std::pair<std::string, std::string>>;
// Whether `name` (a file name without its directory) is one of `series`'.
bool is_numbered_file(const std::string& name, const NumberedSeries& series);
// Whether the file `path` lies in the directory `dir` (either named by any path).
bool is_in_directory(const std::string& path, const std::string& dir);
// Removes from `dir` the regular files named as `series`' (an earlier run's numbered files, which
// would mix with a new run's); returns how many.
int64_t remove_numbered_files(const std::string& dir, const NumberedSeries& series);
// A text file written whole: to a temporary file (make_temp_beside) renamed over PATH (a device or
// a pipe is written in place); IoError on any failed write.
void write_text_file(const std::string& path, const std::string& text, const std::string& what);

struct SummaryInput {
  std::string scene;
  std::string status;  // ok | static | interrupted | failed (INTERFACE.md)
  int exit_code = 0;
  double wall_s = 0;
  int64_t steps_run = 0;
  double average_from = 0;
  std::vector<std::string> warnings;
  std::vector<ProfileSeries> profiles;
  StepFailure failure;  // a failure that is not the simulation's state's (the preparation's)
  // The preparation before the run (procedure O), when there was one: its steps, wall time and
  // stage times, apart from the run's.
  const PreparationReport* preparation = nullptr;
  // A failed run: the last good state, whose step, time and fields the summary reports (the
  // failure and the stage timings are the simulation's state's).
  const State* kept = nullptr;
};
// Summary JSON of INTERFACE.md. Throws IoError.
void write_summary(const std::string& path, const SummaryInput& in, const Simulation& sim, const StatsWriter& stats);

// Fields on one grid as VTK ImageData (.vti): Origin at the grid's lower corner, Spacing h, the
// values as CellData (they are cell averages at the cell centres). Throws IoError, and
// std::invalid_argument for fields on different grids or of the wrong size.
void write_vti(const std::string& path, const std::vector<GridField>& fields);

// VTK XML output for ParaView and OVITO: DIR/grains_NNNNNN.vtu (points with radius, velocity,
// angular velocity, force, id, frozen), DIR/contacts_NNNNNN.vtp (one line per contact with its
// normal and tangential force), DIR/fields_NNNNNN.vti for the grid fields given (a fluid's) and
// DIR/index.pvd (the time series, its parts numbered in that order). A scene without grains
// writes no grains or contacts files.
class VtkWriter {
 public:
  // Creates dir (an earlier run's numbered files in it removed); throws IoError.
  explicit VtkWriter(std::string dir);
  void write(const Model& m, const State& s, const std::vector<GridField>& fields = {});
  int64_t count() const { return count_; }
  int64_t removed() const { return removed_; }  // an earlier run's files removed from dir
  // The names it writes in its directory: the numbered series and index.pvd.
  static const NumberedSeries& series();
  static bool owns(const std::string& path, const std::string& dir);

 private:
  std::string write_fields(const std::vector<GridField>& fields);  // its file's name, "" for none
  void write_entry(double t, const std::string& grains, const std::string& contacts, const std::string& grid);
  struct Entry {
    double t;
    std::string grains, contacts, fields;  // fields: "" when none
  };
  std::string dir_;
  int64_t count_ = 0;
  int64_t removed_ = 0;
  std::vector<Entry> entries_;
};

// Checkpoints: binary, versioned, with a checksum; written to a temporary file then renamed,
// so an interrupted write leaves the previous checkpoint intact. A checkpoint belongs to a system
// (dimension, grains, walls, periodicity) and records the scene's name and parameters.
void write_checkpoint(const std::string& path, const Model& m, const State& s);
// Throws IoError for unreadable, corrupt, other-system or other-version files (saying what
// differs, or which version was found). Parameters of the scene that differ from those recorded
// (other run parameters, steered values) are not an error: `differences` receives them as
// "contact.friction = 0.1 in the checkpoint, 0.5 in the scene". Grains frozen in the checkpoint
// and free in the scene (the shell's `freeze` before it was saved) make another system, unless
// `frozen` is given: it then receives them (1 by grain id), for Simulation::freeze_grains before
// the state is restored.
State read_checkpoint(const std::string& path, const Model& m, std::vector<std::string>* differences = nullptr,
                      std::vector<uint8_t>* frozen = nullptr);
// Every key of the schema, with the indices of the scene's tables, and its resolved value as text
// (given, else the default; "" when neither): what checkpoints record.
std::vector<std::pair<std::string, std::string>> scene_parameters(const SceneDesc& d);

}  // namespace silt
