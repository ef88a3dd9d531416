// The shell's outputs during runs: the samples of the observables (`stats`), frames and VTK files.
#include <algorithm>
#include <filesystem>

#include "shell/session.hpp"
#include "shell/table.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt::shell {

// A new series for the same observables, to `path` ("" none), holding the samples of `old`
// (written to the file as they are added).
StatsWriter Session::reseries(const StatsWriter& old, const std::string& path) {
  StatsWriter next(path, old.names());
  for (size_t r = 0; r < old.rows().size(); ++r)
    next.add(old.rows()[r], old.times()[r], r + 1 == old.rows().size() ? old.last_step() : -1);
  next.flush();  // throws IoError when the file cannot take them
  return next;
}

void Session::cmd_stats(const Command& c) {
  sim();
  const auto& a = c.args;
  if (a.size() == 1 && a[0].text == "reset") {
    // The samples in memory go; a file they went to is closed as it is (it was opened again,
    // emptied, for the new series).
    size_t n = 0;
    at_boundary([&] {
      n = stats_->rows().size();
      note_output_errors();                              // the writer replaced: its error stays to be reported
      std::vector<std::string> names = stats_->names();  // (emplace destroys the series first)
      stats_.emplace("", std::move(names));
    });
    out_ << "stats reset: " << n << " sample(s) discarded";
    if (!stats_file_.empty()) out_ << "; " << stats_file_ << " closed as it is (stats FILE.csv writes the new series)";
    out_ << "\n";
    stats_file_.clear();
    return;
  }
  if (a.size() == 1 && a[0].text == "off") {
    if (stats_file_.empty()) throw std::runtime_error("the samples go to no file (stats FILE.csv [every N])");
    at_boundary([&] {
      note_output_errors();  // the writer replaced: its error stays to be reported
      stats_.emplace(reseries(*stats_, ""));
    });
    out_ << "stats no longer written to " << stats_file_ << "\n";
    stats_file_.clear();
    stats_every_ = 0;
    return;
  }
  double since = -std::numeric_limits<double>::infinity();
  if (!a.empty() && a[0].text == "since") {
    if (a.size() != 2) throw ParseError(a[0].col, "usage: stats since T");
    std::string_view v(a[1].text);
    if (!v.empty() && v.back() == 's') v.remove_suffix(1);
    const auto t = parse_number(v);
    if (!t) throw ParseError(a[1].col, "'" + a[1].text + "' is not a time (e.g. 10 or 10s)");
    since = *t;
  } else if (!a.empty()) {
    // stats FILE.csv [every N]
    if (a.size() != 1 && (a.size() != 3 || a[1].text != "every"))
      throw ParseError(c.name_col, "usage: stats [since T | reset | FILE.csv [every N] | off]");
    // (`stats every` started a file named "every" in the current directory)
    if (a[0].text == "every" || a[0].text == "since")
      throw ParseError(a[0].col, "'" + a[0].text + "' is a word of the command, not a file: stats FILE.csv every N");
    const int64_t every = a.size() == 3 ? parse_every(a[2]) : 0;
    require_stopped("cannot change where the samples go");
    check_not_inputs(a[0].text, "stats");
    check_not_restored(a[0].text, "stats");
    check_not_series_file(a[0].text, "stats");
    // (an existing file was replaced without a word)
    std::error_code ec;
    const bool replaces = std::filesystem::is_regular_file(a[0].text, ec) && a[0].text != stats_file_;
    const auto old_bytes = replaces ? std::filesystem::file_size(a[0].text, ec) : 0;
    const bool sized = replaces && !ec;
    stats_.emplace(reseries(*stats_, a[0].text));
    stats_error_noted_ = false;
    stats_file_ = a[0].text;
    stats_every_ = every;
    out_ << "stats to " << stats_file_ << " (" << stats_->rows().size() << " sample(s) so far), every "
         << (every > 0 ? every : sim().model().sample_every) << " steps";
    if (replaces)
      out_ << "; it replaces the file that was there" << (sized ? " (" + std::to_string(old_bytes) + " bytes)" : "");
    out_ << "\n";
    return;
  }
  std::vector<std::vector<double>> rows;
  std::vector<double> times;
  at_boundary([&] {  // a background run adds to them
    rows = stats_->rows();
    times = stats_->times();
  });
  std::vector<size_t> kept;
  for (size_t r = 0; r < rows.size(); ++r)
    if (at_or_after(times[r], since)) kept.push_back(r);
  if (kept.empty())
    throw std::runtime_error(rows.empty() ? "no samples yet (run first)"
                                          : "no sample with t >= " + format_number(since) + " s");
  // The error of the mean by block averaging, to two digits; "(lower bound)" when the blocks
  // never became independent.
  Table t({"observable", "unit", "mean", "error", "", "last", "samples"},
          {false, false, true, true, false, true, true});
  const auto& names = stats_->names();
  const Observer units(sim().model(), names);
  for (size_t k = 0; k < names.size(); ++k) {
    std::vector<double> series;
    for (size_t r : kept) series.push_back(rows[r][k]);
    const BlockAverage b = block_average(series);
    const auto [mean, err] = mean_and_error(b.mean, b.err);
    // (a nan sample, mu where stress.yy is 0 at t = 0, made the mean nan without a word)
    t.add({names[k], units.units()[k], mean, err, b.converged ? "" : "(lower bound)", format_value(series.back()),
           std::to_string(b.n) + (b.nans > 0 && b.nans < b.n ? " (" + std::to_string(b.nans) + " nan)" : "")});
  }
  t.print(out_);
}

void Session::check_not_series_dir(const std::string& dir, bool (*owns)(const std::string&, const std::string&),
                                   const std::string& what) const {
  if (!stats_file_.empty() && owns(stats_file_, dir))
    throw IoError("cannot write " + what + " in '" + dir + "': the stats file being written, " + stats_file_ +
                  ", has the name of one of them there; `stats off` first");
}

void Session::cmd_frames(const Command& c) {
  sim();
  if (c.args.size() == 1 && c.args[0].text == "off") {
    require_stopped("cannot change frames");
    if (frames_) frames_->finish();
    const int64_t n = frames_ ? frames_->written() : 0;
    note_output_errors();
    frames_.reset();
    out_ << "frames off (" << n << " written)\n";
    report_output_errors();
    return;
  }
  if (c.args.size() != 3 || c.args[1].text != "every")
    throw ParseError(c.name_col, "usage: frames DIR every N | frames off");
  const int64_t every = parse_every(c.args[2]);
  require_stopped("cannot change frames");
  check_not_series_dir(c.args[0].text, render::FrameWriter::owns, "frames");
  note_output_errors();  // the writer replaced: its error stays to be reported
  frames_ = std::make_unique<render::FrameWriter>(c.args[0].text);
  frames_dir_ = c.args[0].text;
  frames_error_noted_ = false;
  frames_every_ = every;
  frames_last_step_ = -1;
  out_ << "frames to " << c.args[0].text << " every " << frames_every_ << " steps";
  if (frames_->removed() > 0) out_ << " (" << frames_->removed() << " frame(s) of an earlier run removed)";
  out_ << "\n";
}

void Session::cmd_vtk(const Command& c) {
  sim();
  if (c.args.size() == 1 && c.args[0].text == "off") {
    require_stopped("cannot change the VTK output");
    const int64_t n = vtk_ ? vtk_->count() : 0;
    vtk_.reset();
    out_ << "vtk off (" << n << " written)\n";
    report_output_errors();
    return;
  }
  if (c.args.size() != 3 || c.args[1].text != "every") throw ParseError(c.name_col, "usage: vtk DIR every N | vtk off");
  const int64_t every = parse_every(c.args[2]);
  require_stopped("cannot change the VTK output");
  check_not_series_dir(c.args[0].text, VtkWriter::owns, "vtk");
  note_output_errors();  // the writer replaced: its error stays to be reported
  vtk_ = std::make_unique<VtkWriter>(c.args[0].text);
  vtk_dir_ = c.args[0].text;
  vtk_every_ = every;
  vtk_error_.clear();
  vtk_error_noted_ = false;
  vtk_last_step_ = -1;
  out_ << "vtk to " << c.args[0].text << " every " << vtk_every_ << " steps";
  if (vtk_->removed() > 0) out_ << " (" << vtk_->removed() << " file(s) of an earlier run removed)";
  out_ << "\n";
}

}  // namespace silt::shell
