// The lubrication laws of Peyneau (2009) eq. 1.26-1.29 and the constant cutoff of Table 2.3.
#include <doctest/doctest.h>

#include <initializer_list>

#include "paste/lubrication_laws.hpp"

using namespace silt::paste;

namespace {

LubricationLaw law(double h_min, Cutoff c = Cutoff::kLinear) { return {2.0, h_min, 0.5, c}; }

}  // namespace

TEST_CASE("above the cutoff the laws are the smooth-sphere ones (eq. 1.26, 1.27), none beyond h_max") {
  const double r = 0.5, eta = 2.0;
  const double pi = std::numbers::pi;
  for (double h : {1e-3, 0.01, 0.3, 0.5}) {
    CHECK(xi_normal(h, r, law(1e-3)) == doctest::Approx(1.5 * pi * eta * r * r / h).epsilon(1e-14));
    CHECK(xi_tangential(h, r, law(1e-3)) == doctest::Approx(pi * eta * r * std::log(2 * r / h)).epsilon(1e-14));
  }
  CHECK(xi_normal(0.5000001, r, law(1e-3)) == 0);
  CHECK(xi_tangential(0.6, r, law(1e-3)) == 0);
}

TEST_CASE("the linear cutoff is continuous and C1 at h_min, continuous at contact, constant in contact") {
  const double r = 0.45;
  for (double h_min : {1e-1, 1e-3, 1e-8}) {
    CAPTURE(h_min);
    const LubricationLaw l = law(h_min);
    const double d = h_min * 1e-7;
    for (auto xi : {xi_normal, xi_tangential}) {
      CHECK(xi(h_min - d, r, l) == doctest::Approx(xi(h_min + d, r, l)).epsilon(1e-6));
      // The slopes on both sides of h_min agree (the linear branch is the tangent).
      const double left = (xi(h_min - d, r, l) - xi(h_min - 2 * d, r, l)) / d;
      const double right = (xi(h_min + 2 * d, r, l) - xi(h_min + d, r, l)) / d;
      CHECK(left == doctest::Approx(right).epsilon(1e-4));
      CHECK(xi(0, r, l) == doctest::Approx(xi(-1e-12, r, l)).epsilon(1e-12));
      CHECK(xi(-0.1, r, l) == xi(-1e-3, r, l));
      CHECK(xi(-0.1, r, l) > xi(h_min, r, l));
    }
    // In contact: xi_N = 3 pi eta R^2 / h_min, xi_T = pi eta R (1 + ln(2R/h_min)).
    CHECK(xi_normal(-1, r, l) == doctest::Approx(3 * std::numbers::pi * 2.0 * r * r / h_min));
    CHECK(xi_tangential(-1, r, l) == doctest::Approx(std::numbers::pi * 2.0 * r * (1 + std::log(2 * r / h_min))));
  }
}

TEST_CASE("in contact, xi_N / xi_T grows as the roughness vanishes, as the digest computes") {
  // R_eq = a / 2 (two grains of diameter a = 1): 4.5, 27, 190, 1.2e4, 7.7e6 for h_min/a = 1e-1,
  // 1e-2, 1e-3, 1e-5, 1e-8.
  const double r = 0.5;
  const double expected[] = {4.5, 27, 190, 1.2e4, 7.7e6};
  const double h_mins[] = {1e-1, 1e-2, 1e-3, 1e-5, 1e-8};
  for (int k = 0; k < 5; ++k) {
    CAPTURE(h_mins[k]);
    const double ratio = xi_normal(-1, r, law(h_mins[k])) / xi_tangential(-1, r, law(h_mins[k]));
    CHECK(ratio == doctest::Approx(expected[k]).epsilon(0.05));
  }
}

TEST_CASE("the constant cutoff holds the value at h_min from h_min down") {
  const LubricationLaw c = law(1e-3, Cutoff::kConstant);
  const double r = 0.5;
  for (double h : {9e-4, 1e-5, 0.0, -0.01}) {
    CHECK(xi_normal(h, r, c) == xi_normal(1e-3, r, c));
    CHECK(xi_tangential(h, r, c) == xi_tangential(1e-3, r, c));
  }
  CHECK(xi_normal(-1, r, c) < xi_normal(-1, r, law(1e-3)));  // half the linear cutoff's in contact
}

TEST_CASE("a cutoff beyond R_eq: xi_T stays positive and continuous (held at pi eta R_eq ln 2)") {
  // h_min/a up to 0.5 is allowed; a pair of small grains has R_eq below it (0.0875 for two disks
  // of radius 0.175). The linear branch was the tangent of ln(2 R_eq / h) at h_min, which went
  // negative beyond h_min = 2 R_eq and jumped at h_min: lubrication drove the shear it resists.
  const double r = 0.0875;
  for (double h_min : {0.05, 0.0875, 0.1, 0.2, 0.3, 0.49}) {
    CAPTURE(h_min);
    for (Cutoff c : {Cutoff::kLinear, Cutoff::kConstant}) {
      const LubricationLaw l{1.0, h_min, 0.5, c};
      const double d = h_min * 1e-9;
      for (double h : {-0.1, 0.0, h_min / 2, h_min - d, h_min, h_min + d, 0.45}) CHECK(xi_tangential(h, r, l) > 0);
      CHECK(xi_tangential(h_min - d, r, l) == doctest::Approx(xi_tangential(h_min + d, r, l)).epsilon(1e-6));
      CHECK(xi_tangential(-0.1, r, l) >= xi_tangential(h_min, r, l));
    }
  }
}
