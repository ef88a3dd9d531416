// Aligned text tables and number formats for output that a person reads.
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace silt::shell {

class Table {
 public:
  // Columns named by `header`; those marked in `right` (numbers) are aligned on the right.
  explicit Table(std::vector<std::string> header, std::vector<bool> right = {})
      : header_(std::move(header)), right_(std::move(right)) {
    right_.resize(header_.size(), false);
  }
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  size_t rows() const { return rows_.size(); }
  void print(std::ostream& o) const;

 private:
  std::vector<std::string> header_;
  std::vector<bool> right_;
  std::vector<std::vector<std::string>> rows_;
};

// x with `decimals` digits after the point ("63.2").
std::string fixed(double x, int decimals);

// A value for a person, with its unit when it has one: six significant digits (format_number),
// whole numbers (steps, counts) in full ("1234567", not "1.23457e+06"); "0.25 m/s".
std::string format_value(double x, const std::string& unit = "");

// A measured mean and the error of it: the error to two significant digits and the mean to the
// same decimal place ("0.731" and "0.067", "30200" and "6800", "1.500e-09" and "2.3e-11"); six
// significant digits each (format_number) when the error is zero or not finite.
std::pair<std::string, std::string> mean_and_error(double mean, double err);

}  // namespace silt::shell
