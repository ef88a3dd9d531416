#include "shell/command_parser.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "silt/limits.hpp"
#include "silt/text.hpp"

namespace silt::shell {

namespace {

// The column of byte i of a line as a terminal shows it: characters, not bytes (after an 'é' the
// columns were one too many).
int column_of(std::string_view line, size_t i) {
  int col = 1;
  for (size_t k = 0; k < i && k < line.size(); ++k)
    if ((static_cast<unsigned char>(line[k]) & 0xC0) != 0x80) ++col;
  return col;
}

}  // namespace

std::optional<Command> parse_line(std::string_view line) {
  std::vector<Token> words;
  size_t i = 0;
  const size_t n = line.size();
  while (i < n) {
    const char c = line[i];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
      ++i;
      continue;
    }
    if (c == '#') break;
    Token t;
    t.col = column_of(line, i);
    const size_t start = i;
    if (c == '[' || c == '{') {
      // A list or an inline table, as on the command line and in TOML: ["grains", "chains"],
      // {a = 1}; blanks, quotes of both kinds and nested brackets inside, one word up to its
      // closing bracket ({a = 1} was three words, and a ']' in 'single quotes' ended a list).
      // A '#' outside quotes would start a TOML comment to the end of the line (the list then
      // never ended), a closing bracket must be of the kind opened ([32, 32} passed), and a tab
      // outside quotes is a blank (it was echoed as '?').
      std::string open;
      char quote = 0;
      size_t quote_at = 0;  // (an unterminated quote was blamed on the list's '[')
      while (i < n) {
        const char d = line[i];
        if (is_control(d) && d != '\t') throw ParseError(column_of(line, i), "control character");
        t.text += quote == 0 && d == '\t' ? ' ' : d;
        ++i;
        if (quote != 0) {
          if (quote == '"' && d == '\\' && i < n) {
            if (is_control(line[i]) && line[i] != '\t') throw ParseError(column_of(line, i), "control character");
            t.text += line[i++];
          } else if (d == quote) {
            quote = 0;
          }
          continue;
        }
        if (d == '"' || d == '\'') {
          quote = d;
          quote_at = i - 1;
        } else if (d == '#') {
          throw ParseError(column_of(line, i - 1), "a '#' inside a list or table (quote it: a '#' starts a comment)");
        } else if (d == '[' || d == '{') {
          open += d;
        } else if (d == ']' || d == '}') {
          if ((d == ']') != (open.back() == '['))
            throw ParseError(column_of(line, i - 1), std::string("a '") + d + "' closes a '" + open.back() + "'");
          open.pop_back();
          if (open.empty()) break;
        }
      }
      const bool list = c == '[';
      if (quote != 0) throw ParseError(column_of(line, quote_at), "unterminated quote");
      if (!open.empty())
        throw ParseError(t.col, list ? "a list without its closing ]" : "a table without its closing }");
      if (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '#' && line[i] != '\r' && line[i] != '\n')
        throw ParseError(column_of(line, i),
                         list ? "a list must be followed by a blank" : "a table must be followed by a blank");
    } else if (c == '"') {
      ++i;
      bool closed = false;
      while (i < n) {
        // (control bytes and DEL were taken inside quotes, and a file name could hold them)
        if (is_control(line[i]) && line[i] != '\t') throw ParseError(column_of(line, i), "control character");
        if (line[i] == '\\' && i + 1 < n && (line[i + 1] == '"' || line[i + 1] == '\\')) {
          t.text += line[i + 1];
          i += 2;
        } else if (line[i] == '"') {
          ++i;
          closed = true;
          break;
        } else {
          t.text += line[i++];
        }
      }
      if (!closed) throw ParseError(t.col, "unterminated quote");
      t.raw = line.substr(start, i - start);
      if (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '#' && line[i] != '\r' && line[i] != '\n')
        throw ParseError(column_of(line, i), "a quoted word must be followed by a blank");
    } else if (c == '\'') {
      // A literal word, as TOML's 'single quotes': blanks inside, no escapes ('a b' was two words).
      const size_t close = line.find('\'', i + 1);
      if (close == std::string::npos) throw ParseError(t.col, "unterminated quote");
      t.text = line.substr(i + 1, close - i - 1);
      t.raw = line.substr(i, close - i + 1);
      for (size_t k = i + 1; k < close; ++k)
        if (is_control(line[k]) && line[k] != '\t') throw ParseError(column_of(line, k), "control character");
      i = close + 1;
      if (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '#' && line[i] != '\r' && line[i] != '\n')
        throw ParseError(column_of(line, i), "a quoted word must be followed by a blank");
    } else {
      while (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '\r' && line[i] != '\n') {
        if (line[i] == '"') throw ParseError(column_of(line, i), "a quote inside a word (quote the whole word)");
        if (is_control(line[i])) throw ParseError(column_of(line, i), "control character");
        t.text += line[i++];
      }
    }
    words.push_back(std::move(t));
  }
  if (words.empty()) return std::nullopt;
  Command cmd;
  cmd.name = words[0].text;
  cmd.name_col = words[0].col;
  cmd.args.assign(words.begin() + 1, words.end());
  return cmd;
}

const std::vector<CommandSpec>& command_specs() {
  static const std::vector<CommandSpec> specs = {
      {"load", "load FILE", "load a scene", "Reads and compiles FILE. On an error the previous scene stays loaded.", 1,
       1, ArgKind::kFile},
      {"reload", "reload", "load the current scene file again",
       "Re-reads the scene file (with the values changed by set), from t = 0.", 0, 0, ArgKind::kNone},
      {"check", "check", "describe the loaded scene",
       "Prints the compiled model: dimension, grains, laws, time step and its stability limit, stages.", 0, 0,
       ArgKind::kNone},
      {"run", "run [N | Ts | until EXPR | until static | until steady]", "run in the foreground",
       "Runs N steps, or T seconds of simulated time (\"run 0.5s\"), or until a condition on observables holds (\"run "
       "until t >= 1 and ke < 1e-6\", blanks optional: \"run until t>=1\"; \"and\" binds tighter than \"or\"; tested "
       "at every step when it reads only t, "
       "step "
       "and dt, else every 10 steps (the run then stops up to 9 steps after it first holds) and in between where a "
       "term's window of t and step, such as step == N, closes before the next test; a condition that t and step have "
       "made impossible ends the run; a comparison of a value only a step makes, such as fluid.change_rate, does "
       "not hold before the first step (dt and a paste's solver values do: the state a run starts from has them); t "
       "within 1e-9 of a value is at it, whatever its sum of steps' rounding), or "
       "until the packing is "
       "static (the "
       "scene's run.static_* criterion), or until the fluid is steady (run.steady_tol). Alone, it runs to the scene's "
       "end (run.steps or run.time), stopping when static or steady if the scene says run.stop_when_static or "
       "run.stop_when_steady, as silt run does. Ctrl-C pauses at the next step boundary.",
       0, -1, ArgKind::kObservable},
      {"start", "start [N | Ts | until EXPR | until static | until steady]", "run in the background",
       "Runs in the background while the prompt stays responsive; stop pauses it. Alone, it runs to the scene's end "
       "as run does. set, get, print and the others act at the next step boundary.",
       0, -1, ArgKind::kObservable},
      {"stop", "stop", "pause a background run", "Stops a background run at the next step boundary.", 0, 0,
       ArgKind::kNone},
      {"wait", "wait", "wait for a background run to end",
       "Waits until a background run ends at its length or condition (Ctrl-C pauses it), so that a script that starts "
       "a run and then looks at its end does the same however fast the machine is.",
       0, 0, ArgKind::kNone},
      {"set", "set KEY VALUE [KEY VALUE...]", "change scene values",
       "Changes a value of the scene (dotted key, TOML value). Steerable values (params shows them) act at the next "
       "step boundary, even while a run goes on; the others are refused while running, and otherwise recompile the "
       "scene (the state is kept when the grains are the same). Several pairs are one change, compiled once, for "
       "values valid only together (\"set domain.hi [2.0, 1.0] fluid.cells [128, 64]\"); it recompiles, so it needs "
       "the run stopped.",
       2, -1, ArgKind::kKey},
      {"get", "get KEY", "show a scene value", "Prints the value of a scene key (given or default), with its unit.", 1,
       1, ArgKind::kKey},
      {"params", "params [PREFIX]", "list the scene keys",
       "Lists every scene key (or those starting with PREFIX) with its value, unit, range and whether it is steerable.",
       0, 1, ArgKind::kKey},
      {"print", "print OBS...", "print observables now", "Prints the current values of the observables.", 1, -1,
       ArgKind::kObservable},
      {"watch", "watch OBS... every N | watch off", "print observables during runs",
       "Prints the observables every N steps while a run goes on; watch off stops it.", 1, -1, ArgKind::kObservable},
      {"stats", "stats [since T | reset | FILE.csv [every N] | off]", "means of the observables",
       "Mean, error of the mean (block averaging) and last value of the observables sampled since the scene was "
       "loaded or the samples reset; since T: over the samples with t >= T. reset discards the samples (a new regime "
       "after steering). FILE.csv writes the samples to a file, those so far and each new one as it comes, and "
       "samples every N steps from now on (default: output.every); off closes the file.",
       0, 3, ArgKind::kFile},
      {"profile", "profile", "time per stage", "Wall time spent in each stage of the step graph.", 0, 0,
       ArgKind::kNone},
      {"render", "render FILE.png [ITEM...]", "draw the current state",
       "Writes a PNG of the current state with the scene's [render] settings; ITEMs (grains chains lubrication field "
       "colorbar time scalebar box) replace render.draw.",
       1, -1, ArgKind::kFile},
      {"frames", "frames DIR every N | frames off", "write frames during runs",
       "Writes DIR/frame_000000.png, ... every N steps while running; frames off stops.", 1, 3, ArgKind::kFile},
      {"vtk", "vtk DIR every N | vtk off", "write VTK files during runs",
       "Writes DIR/grains_000000.vtu, contacts, and DIR/index.pvd for ParaView or OVITO every N steps while running; "
       "vtk off stops.",
       1, 3, ArgKind::kFile},
      {"save", "save FILE", "write a checkpoint",
       "Writes a checkpoint of the current state (atomically: a temporary file renamed).", 1, 1, ArgKind::kFile},
      {"restore", "restore FILE", "read a checkpoint", "Continues from a checkpoint of the same system.", 1, 1,
       ArgKind::kFile},
      {"reset", "reset", "back to t = 0",
       "Returns to the scene's initial state as it stands: the values given by set, and the grains frozen, are kept "
       "(reload reads the file again).",
       0, 0, ArgKind::kNone},
      {"freeze", "freeze AXIS < VALUE | freeze AXIS > VALUE", "freeze grains",
       "Freezes the free grains whose centre is below (or above) VALUE along AXIS (x, y or z): they stop for good. "
       "A checkpoint saved then makes a rough base for another scene ([[grains]] frozen_from = FILE).",
       3, 3, ArgKind::kNone},
      {"fields", "fields [PREFIX]", "list the state's fields",
       "Lists every field of the state (or those starting with PREFIX): module, extent, type, entries, bytes, unit, "
       "and the stage that writes it.",
       0, 1, ArgKind::kNone},
      {"field", "field NAME [K]", "print a field of the state",
       "Prints a scalar field, or entry K of an array (for a per-grain field, grain K by its id; without K, its "
       "smallest, largest and mean value).",
       1, 2, ArgKind::kNone},
      {"hash", "hash", "a fingerprint of the state",
       "Prints a 64-bit hash of every array and scalar of the state: equal hashes mean bitwise equal states (a "
       "restored run against an uninterrupted one, runs on other thread counts).",
       0, 0, ArgKind::kNone},
      {"source", "source SCRIPT", "run commands from a file",
       "Runs the commands of SCRIPT (relative files: the current directory, else the script's), stopping at its first "
       "error or at Ctrl-C.",
       1, 1, ArgKind::kFile},
      {"help", "help [COMMAND]", "list commands, or explain one",
       "help alone lists the commands; help COMMAND explains it.", 0, 1, ArgKind::kCommand},
      {"quit", "quit", "leave the shell", "Stops any run and leaves (EOF, Ctrl-D, does the same).", 0, 0,
       ArgKind::kNone},
  };
  return specs;
}

const CommandSpec* find_command(std::string_view name) {
  for (const CommandSpec& s : command_specs())
    if (s.name == name) return &s;
  if (name == "exit") return find_command("quit");
  return nullptr;
}

std::string suggest_command(std::string_view name) {
  std::string best;
  size_t best_d = std::max<size_t>(2, name.size() / 3) + 1;
  for (const CommandSpec& s : command_specs()) {
    const size_t d = edit_distance(name, s.name, best_d);
    if (d < best_d) {
      best_d = d;
      best = s.name;
    }
  }
  return best;
}

const CommandSpec& check_command(const Command& c) {
  const CommandSpec* s = find_command(c.name);
  if (!s) {
    std::string msg = "unknown command '" + c.name + "'";
    if (const std::string hint = suggest_command(c.name); !hint.empty()) msg += "; did you mean '" + hint + "'?";
    throw ParseError(c.name_col, msg + " (help lists the commands)");
  }
  const int n = static_cast<int>(c.args.size());
  if (n < s->min_args || (s->max_args >= 0 && n > s->max_args)) {
    const int col = n > s->max_args && s->max_args >= 0 ? c.args[s->max_args].col : c.name_col;
    throw ParseError(col, "usage: " + s->usage);
  }
  // (`stats ""` said the samples went to a file and wrote none; `save ""` gave the system's words)
  if (s->completes == ArgKind::kFile && n > 0 && c.args[0].text.empty())
    throw ParseError(c.args[0].col, "an empty path: give a file or directory");
  return *s;
}

std::optional<double> parse_number(std::string_view s) {
  // (strtod reads hexadecimal: `--time 0x10` ran 16 s)
  if (s.empty() || s.size() > 64 || s.find_first_of("xXpP") != std::string_view::npos) return std::nullopt;
  const std::string str(s);
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(str.c_str(), &end);
  if (end != str.c_str() + str.size() || errno == ERANGE || !std::isfinite(x)) return std::nullopt;
  return x;
}

std::optional<int64_t> parse_count(std::string_view s, int64_t least) {
  const auto n = parse_number(s);
  if (!n || *n < static_cast<double>(least) || *n != std::floor(*n) || *n > static_cast<double>(kMaxRunSteps))
    return std::nullopt;
  return static_cast<int64_t>(*n);
}

int64_t parse_every(const Token& t) {
  const auto n = parse_count(t.text, 1);
  if (!n) throw ParseError(t.col, "every needs a whole number of steps from 1 to 9.2e18");
  return *n;
}

namespace {

bool compare(const Clause& c, double v) {
  // t is a sum of steps, whose rounding leaves it off the value it shows ("t = 0.0003" is
  // 3.0000000000000003e-4 after three steps of 1e-4, and "t <= 0.0003" never held): within 1e-9
  // of a value (a billion steps' rounding), t is at it.
  if (c.observable == "t" && at_time(v, c.value)) return c.op == "<=" || c.op == ">=" || c.op == "==";
  if (c.op == "<") return v < c.value;
  if (c.op == "<=") return v <= c.value;
  if (c.op == ">") return v > c.value;
  if (c.op == ">=") return v >= c.value;
  if (c.op == "==") return v == c.value;
  return v != c.value;
}

// Whether the clauses of [first, last) on t and step hold at (t, step).
bool clock_holds(const std::vector<Clause>& clauses, size_t first, size_t last, double t, int64_t step) {
  bool holds = true;
  for (size_t k = first; k < last && holds; ++k) {
    const Clause& c = clauses[k];
    if (c.observable == "t") holds = compare(c, t);
    if (c.observable == "step") holds = compare(c, static_cast<double>(step));
  }
  return holds;
}

}  // namespace

bool Condition::has_window() const {
  return std::any_of(clauses.begin(), clauses.end(), [](const Clause& c) {
    return (c.observable == "t" || c.observable == "step") && (c.op == "<" || c.op == "<=" || c.op == "==");
  });
}

bool Condition::time_window_open(double t, int64_t step) const {
  for (size_t first = 0, last = 0; first < clauses.size(); first = last) {
    last = term_end(first);
    const bool bounded = std::any_of(
        clauses.begin() + static_cast<std::ptrdiff_t>(first), clauses.begin() + static_cast<std::ptrdiff_t>(last),
        [](const Clause& c) { return c.observable == "t" && (c.op == "<" || c.op == "<=" || c.op == "=="); });
    if (bounded && clock_holds(clauses, first, last, t, step)) return true;
  }
  return false;
}

bool Condition::window_closes(double t, int64_t step, double dt, int64_t ahead) const {
  for (size_t first = 0, last = 0; first < clauses.size(); first = last) {
    last = term_end(first);
    if (clock_holds(clauses, first, last, t, step) &&
        !clock_holds(clauses, first, last, t + static_cast<double>(ahead) * dt, step + ahead))
      return true;
  }
  return false;
}

bool Condition::holds(const std::vector<double>& values, const std::vector<size_t>* column,
                      const std::vector<bool>* unknown) const {
  auto eval = [&](size_t k) {
    return !(unknown && (*unknown)[k]) && compare(clauses[k], values[column ? (*column)[k] : k]);
  };
  // "and" binds tighter than "or": a or b and c is a or (b and c) (it was read left to right, (a or
  // b) and c, and "step >= 60 or t < 0 and dt < 0" never stopped).
  for (size_t first = 0, last = 0; first < clauses.size(); first = last) {
    last = term_end(first);
    bool term = true;
    for (size_t k = first; k < last && term; ++k) term = eval(k);
    if (term) return true;
  }
  return false;
}

size_t Condition::term_end(size_t k) const {
  size_t e = k + 1;
  while (e < clauses.size() && joined_by_and[e - 1]) ++e;
  return e;
}

std::vector<Token> expand_list(const Token& t) {
  // (a quoted word is one word: print "[t, step]" printed two, at columns one too few)
  if (t.text.empty() || t.text[0] != '[' || !t.raw.empty()) return {t};
  std::vector<Token> out;
  const std::string& w = t.text;
  size_t i = 1;
  auto skip_blanks = [&] {
    while (i < w.size() && (w[i] == ' ' || w[i] == '\t')) ++i;
  };
  for (;;) {
    skip_blanks();
    if (i < w.size() && w[i] == ']' && out.empty()) break;  // []
    Token item;
    item.col = t.col + column_of(w, i) - 1;
    if (i < w.size() && (w[i] == '"' || w[i] == '\'')) {
      // "double" with \ escapes, 'single' as it is, as TOML reads them (print ['t'] looked for 't'
      // with its quotes)
      const char quote = w[i++];
      while (i < w.size() && w[i] != quote) {
        if (quote == '"' && w[i] == '\\' && i + 1 < w.size()) ++i;
        item.text += w[i++];
      }
      if (i == w.size()) throw ParseError(item.col, "unterminated quote");
      ++i;
    } else {
      while (i < w.size() && w[i] != ',' && w[i] != ']' && w[i] != ' ' && w[i] != '\t') item.text += w[i++];
    }
    if (item.text.empty()) throw ParseError(item.col, "an empty item in the list");
    out.push_back(std::move(item));
    skip_blanks();
    if (i < w.size() && w[i] == ',') {
      ++i;
      skip_blanks();
      if (i < w.size() && w[i] == ']') break;  // a trailing comma, as TOML allows
      continue;
    }
    if (i < w.size() && w[i] == ']') break;
    throw ParseError(t.col + column_of(w, i) - 1, "expected , or ] in the list");
  }
  return out;
}

std::vector<Token> expand_lists(const std::vector<Token>& args, size_t from) {
  std::vector<Token> out(args.begin(), args.begin() + static_cast<std::ptrdiff_t>(std::min(from, args.size())));
  for (size_t k = from; k < args.size(); ++k)
    for (Token& t : expand_list(args[k])) out.push_back(std::move(t));
  return out;
}

namespace {

// The words of a condition with its comparisons apart: "t>=30" is "t", ">=", "30".
std::vector<Token> split_comparisons(const std::vector<Token>& args, size_t from) {
  std::vector<Token> out;
  for (size_t k = from; k < args.size(); ++k) {
    const std::string& w = args[k].text;
    if (!w.empty() && (w[0] == '[' || w[0] == '{') && args[k].raw.empty())
      throw ParseError(args[k].col, "no brackets in a condition: OBSERVABLE OP NUMBER (t >= 0.5)");
    size_t i = 0;
    while (i < w.size()) {
      Token t;
      t.col = args[k].col + column_of(w, i) - 1;
      const bool op = std::string_view("<>=!").find(w[i]) != std::string_view::npos;
      while (i < w.size() && (std::string_view("<>=!").find(w[i]) != std::string_view::npos) == op) t.text += w[i++];
      out.push_back(std::move(t));
    }
  }
  return out;
}

}  // namespace

RunLength parse_run_length(const std::vector<Token>& all) {
  RunLength r;
  if (all.empty()) throw ParseError(0, "how long? N steps, Ts of simulated time, or until EXPR");
  const Token& first = all[0];
  if (first.text == "until" && all.size() == 2 && (all[1].text == "static" || all[1].text == "steady")) {
    r.kind = all[1].text == "static" ? RunLength::kStatic : RunLength::kSteady;
    return r;
  }
  if (first.text == "until") {
    const std::vector<Token> args = split_comparisons(all, 1);
    r.kind = RunLength::kUntil;
    // OBS OP VALUE [and|or OBS OP VALUE]... Each error is at the word that is wrong or at the one a
    // missing word should follow ("ke < 5 or or t > 1" blamed 't' as not a comparison).
    static const char* ops[] = {"<", "<=", ">", ">=", "==", "!="};
    const auto is_op = [](const std::string& w) {
      return std::string_view("<>=!").find(w[0]) != std::string_view::npos;
    };
    if (args.empty())
      throw ParseError(first.col, "expected: OBSERVABLE OP NUMBER (e.g. t >= 0.5), or static, or steady");
    size_t k = 0;
    for (;;) {
      const Token& obs = args[k];
      for (size_t a = k; a < args.size() && a < k + 3; ++a)
        if (args[a].text.find_first_of("()") != std::string::npos)
          throw ParseError(args[a].col, "no parentheses in a condition: 'and' binds tighter than 'or'");
      if (parse_number(obs.text))
        throw ParseError(obs.col,
                         "'" + obs.text + "' where an observable was expected: OBSERVABLE OP NUMBER (t >= 0.5)");
      if (is_op(obs.text) || obs.text == "and" || obs.text == "or")
        throw ParseError(obs.col,
                         "'" + obs.text + "' where an observable was expected (OBSERVABLE OP NUMBER, e.g. t >= 0.5)");
      if (k + 1 == args.size()) throw ParseError(obs.col, "a comparison after '" + obs.text + "' (< <= > >= == !=)");
      Clause c;
      c.observable = obs.text;
      c.col = obs.col;
      c.op = args[k + 1].text;
      if (std::find(std::begin(ops), std::end(ops), c.op) == std::end(ops))
        throw ParseError(args[k + 1].col, "'" + c.op + "' is not a comparison (< <= > >= == !=)");
      if (k + 2 == args.size()) throw ParseError(args[k + 1].col, "a number after '" + c.op + "'");
      const auto v = parse_number(args[k + 2].text);
      if (!v) throw ParseError(args[k + 2].col, "'" + args[k + 2].text + "' is not a number");
      c.value = *v;
      r.until.clauses.push_back(c);
      k += 3;
      if (k == args.size()) break;
      if (args[k].text != "and" && args[k].text != "or")
        throw ParseError(args[k].col, "'" + args[k].text + "' where 'and' or 'or' was expected");
      r.until.joined_by_and.push_back(args[k].text == "and");
      ++k;
      if (k == args.size()) throw ParseError(args[k - 1].col, "a condition after '" + args[k - 1].text + "'");
    }
    return r;
  }
  if (all.size() > 1) throw ParseError(all[1].col, "one run length: N, Ts or until EXPR");
  const std::string& w = first.text;
  if (!w.empty() && w.back() == 's') {
    const auto t = parse_number(std::string_view(w).substr(0, w.size() - 1));
    if (!t || *t <= 0) throw ParseError(first.col, "'" + w + "' is not a positive time (e.g. 0.5s)");
    r.kind = RunLength::kTime;
    r.time = *t;
    return r;
  }
  const auto n = parse_count(w, 0);
  if (!n) throw ParseError(first.col, "'" + w + "' is not a number of steps (or a time like 0.5s, or until EXPR)");
  r.kind = RunLength::kSteps;
  r.steps = *n;
  return r;
}

std::string quoted_word(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string shown_word(std::string_view text) {
  // (a list, [0, 0, -1] or ["a", 'b'], is one word with its blanks and quotes; a TOML string kept
  // as typed, "a\tb" or 'c', is itself)
  const bool list = text.size() >= 2 && text.front() == '[' && text.back() == ']';
  const bool typed = text.size() >= 2 && (text.front() == '"' || text.front() == '\'') && text.back() == text.front();
  if (typed) return std::string(text);
  const bool plain = !text.empty() && std::none_of(text.begin(), text.end(), [list](char ch) {
    return is_control(ch) || (ch == ' ' && !list) || ch == '\\' || ch == '#' || ((ch == '"' || ch == '\'') && !list);
  });
  if (plain) return std::string(text);
  std::string out = "\"";
  for (const char ch : text) {
    if (ch == '"' || ch == '\\') out += '\\';
    if (is_control(ch)) out += '?';
    else out += ch;
  }
  return out + "\"";
}

std::string printable_line(std::string_view line) {
  std::string out(line);
  for (char& ch : out)
    if (is_control(ch) && ch != '\t') ch = '?';
  return out;
}

std::string_view without_bom(std::string_view line) {
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  if (line.substr(0, kBom.size()) == kBom) line.remove_prefix(kBom.size());
  return line;
}

std::string script_line(std::string_view line, int n) {
  if (n == 1) line = without_bom(line);
  // (a script saved with CRLF ends: its lines were echoed with a '?')
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return std::string(line);
}

}  // namespace silt::shell
