#include "shell/table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "silt/text.hpp"

namespace silt::shell {

void Table::print(std::ostream& o) const {
  std::vector<size_t> w(header_.size());
  for (size_t k = 0; k < header_.size(); ++k) w[k] = header_[k].size();
  for (const auto& r : rows_)
    for (size_t k = 0; k < r.size() && k < w.size(); ++k) w[k] = std::max(w[k], r[k].size());
  auto line = [&](const std::vector<std::string>& r) {
    std::string s;
    for (size_t k = 0; k < w.size(); ++k) {
      const std::string cell = k < r.size() ? r[k] : "";
      const std::string pad(w[k] - cell.size(), ' ');
      s += right_[k] ? pad + cell : cell + pad;
      if (k + 1 < w.size()) s += "  ";
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

std::string fixed(double x, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  return buf;
}

std::string format_value(double x, const std::string& unit) {
  const bool whole = x == std::trunc(x) && std::fabs(x) < 1e15;
  return format_number(x, whole ? 15 : 6) + (unit.empty() ? "" : " " + unit);
}

std::pair<std::string, std::string> mean_and_error(double mean, double err) {
  if (!(err > 0) || !std::isfinite(err) || !std::isfinite(mean)) return {format_number(mean), format_number(err)};
  const int e = static_cast<int>(std::floor(std::log10(err)));  // the error's leading digit
  const int decimals = 1 - e;                                   // keeps two digits of it
  if (decimals >= 0 && decimals <= 10 && std::fabs(mean) < 1e9) return {fixed(mean, decimals), fixed(err, decimals)};
  if (decimals < 0 && std::fabs(mean) < 1e15) {  // rounded to tens, hundreds, ...
    const double unit = std::pow(10.0, -decimals);
    return {fixed(std::round(mean / unit) * unit, 0), fixed(std::round(err / unit) * unit, 0)};
  }
  char m[64], s[64];
  const int mean_digits =
      mean == 0 ? 0 : std::max(0, static_cast<int>(std::floor(std::log10(std::fabs(mean)))) - e + 1);
  std::snprintf(m, sizeof m, "%.*e", mean_digits, mean);
  std::snprintf(s, sizeof s, "%.1e", err);
  return {m, s};
}

}  // namespace silt::shell
