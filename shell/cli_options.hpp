// The command line's numbers read as the shell reads them (`--steps 1e3`, `--time 0.5s`), checked
// with silt's messages rather than the option parser's (whose bounds print with 300 digits), and
// the thread count a request is granted.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "silt/limits.hpp"

namespace silt::cli {

constexpr int64_t kMaxThreads = 4096;
// A whole number from least to most (1000, 1e3).
CLI::Validator whole_number(int64_t least, int64_t most = kMaxRunSteps);
// A time in seconds, >= 0: 0.5 or 0.5s.
CLI::Validator seconds();
// A comma-separated list of observable names with no empty one.
CLI::Validator observable_list();
// A file or directory name that is not empty ("$OUT" of an unset variable wrote nothing, and an
// empty --restore started from t = 0, without a word).
CLI::Validator path_given();
// A scene override KEY=VALUE (its value is checked against the scene later, a scene error).
CLI::Validator key_value();

// The worker threads a run gets for `requested` (0: all cores): at most the cores oneTBB offers
// this process; a request above them is granted that many, and said so on stderr.
int granted_threads(int requested);

}  // namespace silt::cli
