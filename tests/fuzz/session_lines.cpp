#include "session_lines.hpp"

#include <cstdio>
#include <regex>
#include <vector>

#include "shell/command_parser.hpp"
#include "silt/limits.hpp"

namespace silt::fuzz {
namespace {

using shell::Command;
using shell::Token;

Token word(const std::string& text) { return Token{text, 0, ""}; }

// A word that the parser reads back as the same token.
std::string quoted(const std::string& w) {
  const bool bare = !w.empty() && (w[0] == '[' || w.find_first_of(" \t#\"\\") == std::string::npos);
  if (bare) return w;
  std::string q = "\"";
  for (const char c : w) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}

std::string line_of(const Command& c) {
  std::string out = c.name;
  for (const Token& t : c.args) out += " " + quoted(t.text);
  return out;
}

// Paths become names in the current directory: nothing is read or written elsewhere.
bool plain_names(Command& c) {
  bool changed = false;
  for (Token& t : c.args) {
    const auto slash = t.text.rfind('/');
    if (slash == std::string::npos && t.text != "." && t.text != "..") continue;
    t.text = slash == std::string::npos ? "" : t.text.substr(slash + 1);
    if (t.text.empty() || t.text == "." || t.text == "..") t.text = "x";
    changed = true;
  }
  return changed;
}

std::string seconds(double s) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17gs", s);
  return buf;
}

// run and start: every length made at most kFuzzRunSteps. The scene's own length (no argument) is
// cut by the scene files and by bound_value.
bool bound_run(Command& c, const ClockFn& now) {
  if (c.args.empty()) return false;
  shell::RunLength r;
  try {
    r = shell::parse_run_length(c.args);
  } catch (const shell::ParseError&) {
    return false;  // refused as it is
  }
  if (r.kind == shell::RunLength::kSteps) {
    if (r.steps <= kFuzzRunSteps) return false;
    c.args = {word(std::to_string(kFuzzRunSteps))};
    return true;
  }
  const std::optional<Clock> clock = now();
  if (!clock) return false;  // no scene: refused as it is
  if (r.kind == shell::RunLength::kTime) {
    const double steps = r.time / clock->dt;
    if (!(steps > kFuzzRunSteps) || steps > static_cast<double>(silt::kMaxRunSteps))
      return false;  // short, or refused as too long
    c.args = {word(seconds(kFuzzRunSteps * clock->dt))};
    return true;
  }
  // Until a condition, or until the first step that makes it true.
  if (r.kind == shell::RunLength::kUntil) {
    for (const char* w : {"or", "step", ">="}) c.args.push_back(word(w));
    c.args.push_back(word(std::to_string(clock->step + kFuzzRunSteps)));
    return true;
  }
  // Until static (which may never come): as many steps as the others at most. The static test
  // itself runs at the end of the scene's own length (pack_2d stops when static).
  c.args = {word("until"), word("step"), word(">="), word(std::to_string(clock->step + kFuzzRunSteps))};
  return true;
}

// set of a value that makes runs long or frames large.
bool bound_value(Command& c, const ClockFn& now) {
  if (c.args.size() != 2) return false;
  const std::string& key = c.args[0].text;
  std::string& value = c.args[1].text;
  const std::optional<double> x = shell::parse_number(value);
  auto cut = [&](double most, const std::string& to) {
    if (x && *x <= most) return false;
    value = to;  // TOML numbers the shell does not read (9_000, 0x2000) are cut too
    return true;
  };
  if (key == "render.width" || key == "render.height") return cut(kMaxFramePixels, std::to_string(kMaxFramePixels));
  if (key == "run.steps" || key == "prepare.max_steps") return cut(kFuzzRunSteps, std::to_string(kFuzzRunSteps));
  if (key == "run.time") {
    const std::optional<Clock> clock = now();
    if (!clock) return false;
    const std::string most = seconds(kFuzzRunSteps * clock->dt);
    return cut(kFuzzRunSteps * clock->dt, most.substr(0, most.size() - 1));
  }
  return false;
}

}  // namespace

std::string bounded_line(const std::string& line, const ClockFn& now) {
  std::optional<Command> c;
  try {
    c = shell::parse_line(line);
  } catch (const shell::ParseError&) {
    return line;
  }
  if (!c) return line;
  bool changed = plain_names(*c);
  if (c->name == "run" || c->name == "start") changed = bound_run(*c, now) || changed;
  if (c->name == "set") changed = bound_value(*c, now) || changed;
  return changed ? line_of(*c) : line;
}

bool reports_bug(const std::string& err_line) {
  // "error: MESSAGE", "SCRIPT:LINE: MESSAGE" (a sourced script), "failed: MESSAGE" (background).
  static const std::regex prefix(R"(^(error|failed|\S+:[0-9]+): )");
  static const std::regex bug(
      R"(^(step [0-9]+: internal error in stage |\S+\.[ch]pp:[0-9]+: assertion '|vector::|basic_string|std::|bad_|)"
      R"(map::at|unordered_map::at|stoi|stol|stod|_M_|bad optional access|bad variant access))");
  std::smatch m;
  if (!std::regex_search(err_line, m, prefix)) return false;
  return std::regex_search(err_line.begin() + m.length(0), err_line.end(), bug);
}

}  // namespace silt::fuzz
