#include <cerrno>
#include <cstring>

#include "silt/io.hpp"

namespace silt {

StatsWriter::StatsWriter(const std::string& path, std::vector<std::string> names)
    : path_(path), names_(std::move(names)) {
  if (path.empty()) return;
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw IoError("cannot write stats file '" + path + "': " + std::strerror(errno));
  for (size_t k = 0; k < names_.size(); ++k) std::fprintf(file_, "%s%s", k ? "," : "", names_[k].c_str());
  std::fprintf(file_, "\n");
}

StatsWriter::~StatsWriter() {
  if (file_) std::fclose(file_);
}

void StatsWriter::add(const std::vector<double>& row, double t) {
  rows_.push_back(row);
  times_.push_back(t);
  if (!file_) return;
  for (size_t k = 0; k < row.size(); ++k) std::fprintf(file_, "%s%.17g", k ? "," : "", row[k]);
  std::fprintf(file_, "\n");
}

void StatsWriter::flush() {
  if (file_ && std::fflush(file_) != 0) throw IoError("cannot write stats file '" + path_ + "'");
}

}  // namespace silt
