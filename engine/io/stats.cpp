#include <cerrno>
#include <cstring>

#include <stdexcept>
#include <utility>

#include "silt/io.hpp"
#include "silt/limits.hpp"

namespace silt {

StatsWriter::StatsWriter(const std::string& path, std::vector<std::string> names, std::optional<double> stream_from)
    : path_(path), names_(std::move(names)), stream_from_(stream_from) {
  if (stream_from_) streamed_.resize(names_.size());
  if (path.empty()) return;
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw IoError("cannot write stats file '" + path + "': " + std::strerror(errno));
  for (size_t k = 0; k < names_.size(); ++k) std::fprintf(file_, "%s%s", k ? "," : "", names_[k].c_str());
  std::fprintf(file_, "\n");
}

StatsWriter::~StatsWriter() {
  if (file_) std::fclose(file_);
}

StatsWriter::StatsWriter(StatsWriter&& other) noexcept
    : file_(std::exchange(other.file_, nullptr)),
      path_(std::move(other.path_)),
      names_(std::move(other.names_)),
      rows_(std::move(other.rows_)),
      times_(std::move(other.times_)),
      stream_from_(other.stream_from_),
      streamed_(std::move(other.streamed_)),
      last_row_(std::move(other.last_row_)),
      samples_(other.samples_),
      last_step_(other.last_step_),
      error_(std::move(other.error_)) {}

StatsWriter& StatsWriter::operator=(StatsWriter&& other) noexcept {
  if (this != &other) {
    if (file_) std::fclose(file_);
    file_ = std::exchange(other.file_, nullptr);
    path_ = std::move(other.path_);
    names_ = std::move(other.names_);
    rows_ = std::move(other.rows_);
    times_ = std::move(other.times_);
    stream_from_ = other.stream_from_;
    streamed_ = std::move(other.streamed_);
    last_row_ = std::move(other.last_row_);
    samples_ = other.samples_;
    last_step_ = other.last_step_;
    error_ = std::move(other.error_);
  }
  return *this;
}

void StatsWriter::add(const std::vector<double>& row, double t, int64_t step) {
  if (!stream_from_) {
    rows_.push_back(row);
    times_.push_back(t);
  } else {
    if (at_or_after(t, *stream_from_))
      for (size_t k = 0; k < row.size() && k < streamed_.size(); ++k) streamed_[k].add(row[k]);
    last_row_ = row;  // (kept rows have it last)
  }
  ++samples_;
  last_step_ = step;
  if (!file_ || !error_.empty()) return;
  for (size_t k = 0; k < row.size(); ++k) std::fprintf(file_, "%s%.17g", k ? "," : "", row[k]);
  std::fprintf(file_, "\n");
  if (std::fflush(file_) != 0) error_ = std::strerror(errno);
}

BlockAverage StatsWriter::average(size_t k, double since) const {
  if (stream_from_) {
    if (since != *stream_from_) throw std::logic_error("stats streamed from another time than asked");
    return streamed_.at(k).result();
  }
  std::vector<double> series;
  for (size_t r = 0; r < rows_.size(); ++r)
    if (at_or_after(times_[r], since)) series.push_back(rows_[r][k]);
  return block_average(series);
}

size_t StatsWriter::drop_after(double t, int64_t step) {
  size_t kept = 0;
  bool at_t = false;
  for (size_t r = 0; r < rows_.size(); ++r) {
    if (times_[r] > t) continue;
    at_t = times_[r] == t;
    if (kept != r) rows_[kept] = std::move(rows_[r]);  // (a vector moved onto itself is emptied)
    times_[kept++] = times_[r];
  }
  const size_t dropped = rows_.size() - kept;
  rows_.resize(kept);
  times_.resize(kept);
  last_step_ = at_t ? step : -1;
  return dropped;
}

void StatsWriter::flush() {
  if (file_ && error_.empty() && std::fflush(file_) != 0) error_ = std::strerror(errno);
  if (!error_.empty()) throw IoError("cannot write stats file '" + path_ + "': " + error_);
}

}  // namespace silt
