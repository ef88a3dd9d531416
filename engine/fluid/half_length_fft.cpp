// The tables of the half-length transforms (half_length_fft.hpp).
#include "fluid/half_length_fft.hpp"

#include <cmath>
#include <numbers>

namespace silt::fluid {

std::vector<double> half_length_twiddles(int64_t n) {
  std::vector<double> w(static_cast<size_t>(2 * (n / 4 + 1)));
  for (int64_t k = 0; 4 * k <= n; ++k) {
    const double t = 2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
    // Exact at a quarter turn (the middle frequency of N = n / 2 even).
    w[2 * k] = 4 * k == n ? 0.0 : std::cos(t);
    w[2 * k + 1] = 4 * k == n ? -1.0 : -std::sin(t);
  }
  return w;
}

std::vector<double> cosine_twiddles(int64_t n) {
  std::vector<double> c(static_cast<size_t>(2 * (n / 2 + 1)));
  for (int64_t k = 0; 2 * k <= n; ++k) {
    const double t = std::numbers::pi * static_cast<double>(k) / static_cast<double>(2 * n);
    c[2 * k] = std::cos(t);
    c[2 * k + 1] = std::sin(t);
  }
  return c;
}

std::vector<double> face_sine_table(int64_t N) {
  std::vector<double> s(static_cast<size_t>(N / 2 + 1));
  for (int64_t j = 0; 2 * j <= N; ++j)
    s[j] = std::sin(std::numbers::pi * static_cast<double>(j) / static_cast<double>(N));
  return s;
}

}  // namespace silt::fluid
