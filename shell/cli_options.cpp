#include "shell/cli_options.hpp"

#include <tbb/info.h>

#include <cstdio>
#include <iostream>

#include "shell/command_parser.hpp"
#include "silt/scene.hpp"

namespace silt::cli {

CLI::Validator whole_number(int64_t least, int64_t most) {
  return CLI::Validator(
      [least, most](std::string& in) -> std::string {
        auto n = shell::parse_count(in, least);
        if (n && *n > most) n.reset();
        if (!n)
          return "'" + in + "' is not a whole number from " + std::to_string(least) + " to " +
                 (most >= kMaxRunSteps ? std::string(kMaxRunStepsText) : std::to_string(most)) + " (e.g. 1000, 1e3)";
        in = std::to_string(*n);
        return "";
      },
      "N", "whole number");
}

CLI::Validator seconds() {
  return CLI::Validator(
      [](std::string& in) -> std::string {
        std::string_view v(in);
        if (!v.empty() && v.back() == 's') v.remove_suffix(1);
        const auto t = shell::parse_number(v);
        if (!t || *t < 0) return "'" + in + "' is not a time in seconds >= 0 (e.g. 0.5, 0.5s)";
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.17g", *t);
        in = buf;
        return "";
      },
      "T", "seconds");
}

CLI::Validator observable_list() {
  return CLI::Validator(
      [](std::string& in) -> std::string {
        // (an empty list fell back to the scene's, and an empty name was dropped)
        if (in.empty() || in.front() == ',' || in.back() == ',' || in.find(",,") != std::string::npos)
          return "'" + in + "' has an empty name: give observables separated by commas (e.g. t,ke)";
        return "";
      },
      "A,B,...", "observables");
}

CLI::Validator path_given() {
  return CLI::Validator(
      [](std::string& in) -> std::string { return in.empty() ? "an empty path: give a file or directory" : ""; },
      "PATH", "path");
}

CLI::Validator key_value() {
  return CLI::Validator(
      [](std::string& in) -> std::string {
        // (a malformed --set exited 2, as a scene error, not 1)
        try {
          parse_override(in);
        } catch (const SceneError& e) {
          return e.message();
        }
        return "";
      },
      "KEY=VALUE", "scene override");
}

int granted_threads(int requested) {
  const int cores = tbb::info::default_concurrency();
  if (requested <= 0) return cores;
  if (requested <= cores) return requested;
  std::cerr << "silt: --threads " << requested << ": this process can use " << cores << " core(s); running on " << cores
            << " thread(s)\n";
  return cores;
}

}  // namespace silt::cli
