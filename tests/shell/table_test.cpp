// Number formats and alignment of the tables a person reads.
#include <doctest/doctest.h>

#include <limits>
#include <sstream>
#include <string>

#include "shell/table.hpp"
#include "silt/text.hpp"

using namespace silt;
using namespace silt::shell;

TEST_CASE("a mean is shown to the decimal place of its error, the error to two digits") {
  using P = std::pair<std::string, std::string>;
  CHECK(mean_and_error(0.730981, 0.0673304) == P{"0.731", "0.067"});
  CHECK(mean_and_error(20.8699, 4.69214) == P{"20.9", "4.7"});
  CHECK(mean_and_error(0.2107, 0.0016) == P{"0.2107", "0.0016"});
  CHECK(mean_and_error(-0.313729, 0.0313171) == P{"-0.314", "0.031"});
  CHECK(mean_and_error(0.5, 0.0996) == P{"0.500", "0.100"});  // the error rounds up a digit
  CHECK(mean_and_error(30230.4, 6796.66) == P{"30200", "6800"});
  CHECK(mean_and_error(1.5e-9, 2.3e-11) == P{"1.500e-09", "2.3e-11"});
  CHECK(mean_and_error(0.0, 2.3e-11) == P{"0e+00", "2.3e-11"});
  CHECK(mean_and_error(3.25, 0.0) == P{"3.25", "0"});  // no spread: the value itself
  CHECK(mean_and_error(3.25, std::numeric_limits<double>::quiet_NaN()).first == "3.25");
}

TEST_CASE("numbers in significant digits and fixed decimals") {
  CHECK(format_number(0.00818364, 3) == "0.00818");
  CHECK(format_number(63456) == "63456");
  CHECK(fixed(63.2254, 1) == "63.2");
  CHECK(fixed(0.5193, 3) == "0.519");
}

TEST_CASE("a bound not to be passed is printed rounded down, so that the value printed is below it") {
  CHECK(format_bound_below(0.012346, 4) == "0.01234");  // to nearest: 0.01235, above the bound
  CHECK(format_bound_below(0.05, 4) == "0.05");         // an exact bound stays itself
  CHECK(format_bound_below(1.0 / 3.0, 4) == "0.3333");
  CHECK(format_bound_below(2.0 / 3.0, 4) == "0.6666");
  CHECK(format_bound_below(123456.7, 4) == "1.234e+05");
  CHECK(format_bound_below(9.99999e-7, 4) == "9.999e-07");
  for (double x = 1e-9; x < 1e9; x *= 1.37) CHECK(std::stod(format_bound_below(x, 4)) <= x);
}

TEST_CASE("a table aligns text on the left and numbers on the right") {
  Table t({"stage", "seconds"}, {false, true});
  t.add({"contact_forces", "0.519"});
  t.add({"kick", "12.046"});
  std::ostringstream o;
  t.print(o);
  CHECK(o.str() ==
        "stage           seconds\n"
        "--------------  -------\n"
        "contact_forces    0.519\n"
        "kick             12.046\n");
}
