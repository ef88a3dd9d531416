// Aligned text tables for output that a person reads.
#pragma once

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

namespace silt::shell {

class Table {
 public:
  explicit Table(std::vector<std::string> header) : header_(std::move(header)) {}
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  size_t rows() const { return rows_.size(); }
  void print(std::ostream& o) const {
    std::vector<size_t> w(header_.size());
    for (size_t k = 0; k < header_.size(); ++k) w[k] = header_[k].size();
    for (const auto& r : rows_)
      for (size_t k = 0; k < r.size() && k < w.size(); ++k) w[k] = std::max(w[k], r[k].size());
    auto line = [&](const std::vector<std::string>& r) {
      std::string s;
      for (size_t k = 0; k < w.size(); ++k) {
        const std::string cell = k < r.size() ? r[k] : "";
        s += cell;
        if (k + 1 < w.size()) s += std::string(w[k] - cell.size() + 2, ' ');
      }
      while (!s.empty() && s.back() == ' ') s.pop_back();
      o << s << "\n";
    };
    line(header_);
    std::vector<std::string> rule;
    for (size_t k = 0; k < w.size(); ++k) rule.push_back(std::string(w[k], '-'));
    line(rule);
    for (const auto& r : rows_) line(r);
  }

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace silt::shell
