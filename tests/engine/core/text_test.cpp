#include <doctest/doctest.h>

#include <random>
#include <string>

#include "silt/text.hpp"

TEST_CASE("edit distance: Levenshtein, and its bounded search gives min(distance, limit)") {
  using silt::edit_distance;
  CHECK(edit_distance("", "") == 0);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(edit_distance("sitting", "kitten") == 3);
  CHECK(edit_distance("raduis", "radius") == 2);
  CHECK(edit_distance("abc", "") == 3);
  CHECK(edit_distance(std::string(2000, 'x'), "contact.friction", 4) == 4);  // stops on the lengths
  std::mt19937 rng(7);
  auto word = [&] {
    std::string w(rng() % 9, 'a');
    for (char& c : w) c = static_cast<char>('a' + rng() % 3);
    return w;
  };
  for (int k = 0; k < 2000; ++k) {
    const std::string a = word(), b = word();
    const size_t d = edit_distance(a, b), limit = rng() % 6;
    CHECK(edit_distance(a, b, limit) == std::min(d, limit));
  }
}

TEST_CASE("toml_quoted: a TOML basic string that reads back as the text, on one line") {
  using silt::toml_quoted;
  CHECK(toml_quoted("ball") == "\"ball\"");
  CHECK(toml_quoted("") == "\"\"");
  CHECK(toml_quoted("a\"b\\c") == "\"a\\\"b\\\\c\"");
  CHECK(toml_quoted("x\ny\tz\r") == "\"x\\ny\\tz\\r\"");
  CHECK(toml_quoted(std::string("\x07\x1f\x7f", 3)) == "\"\\u0007\\u001F\\u007F\"");
  CHECK(toml_quoted("caf\xc3\xa9") == "\"caf\xc3\xa9\"");  // UTF-8 as it is
}
