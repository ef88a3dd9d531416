// The shell's command language: one command per line, words separated by blanks, "quoted words"
// with \" and \\ escapes, `#` starting a comment. Used by the REPL and by `silt play`; it depends
// on nothing else of silt, so that it can be fuzzed alone (scripts/fuzz.sh).
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace silt::shell {

struct Token {
  std::string text;
  int col = 0;      // 1-based column of the token's first character
  std::string raw;  // a quoted word as typed, its quotes included (a TOML string); "" for others
};

struct Command {
  std::string name;
  int name_col = 1;
  std::vector<Token> args;
};

// A command line that cannot be understood; col is 1-based (0: the whole line).
class ParseError : public std::runtime_error {
 public:
  ParseError(int column, const std::string& message) : std::runtime_error(message), col(column) {}
  int col;
};

// Words of a line; nullopt for a blank or comment-only line. Throws ParseError.
std::optional<Command> parse_line(std::string_view line);
// `text` as one word of a command line: in quotes, with its quotes and backslashes escaped (a
// scene path given to `silt shell`, which the shell loads as `load WORD`).
std::string quoted_word(std::string_view text);
// A word as a message shows what was typed: as it is, or quoted where it would not read back as
// one word (empty, blanks outside a [list], quotes, a backslash, a '#', control bytes); "x y" was
// echoed as x y. A quoted word kept as typed (Token::raw) shows as it is.
std::string shown_word(std::string_view text);
// A script's line without the byte order mark an editor may put at the start of a file (the
// first command was then unknown).
std::string_view without_bom(std::string_view line);
// Line n (from 1) of a script as read: without that mark on the first, and without the carriage
// return of a CRLF end.
std::string script_line(std::string_view line, int n);
// A script line as `silt play` echoes it: control bytes (a binary file read as a script) shown as '?'.
std::string printable_line(std::string_view line);

// The commands, with their arguments and documentation (help, completion).
enum class ArgKind { kNone, kFile, kKey, kObservable, kCommand, kWord };
struct CommandSpec {
  std::string name;
  std::string usage;               // "run N | run Ts | run until EXPR"
  std::string summary;             // one line
  std::string help;                // a paragraph
  int min_args = 0, max_args = 0;  // max -1: any number
  ArgKind completes = ArgKind::kNone;
};
const std::vector<CommandSpec>& command_specs();
const CommandSpec* find_command(std::string_view name);
std::string suggest_command(std::string_view name);  // "" when nothing is close

// Checks a parsed command against its spec: unknown name (with a suggestion) or wrong number of
// arguments. Throws ParseError.
const CommandSpec& check_command(const Command& c);

// A condition of `run until`: observable comparisons joined by `and` / `or`, `and` binding tighter:
// an `or` of terms, each an `and` of clauses.
struct Clause {
  std::string observable;
  std::string op;  // < <= > >= == !=
  double value = 0;
  int col = 0;  // of the observable, for messages
};
struct Condition {
  std::vector<Clause> clauses;
  std::vector<bool> joined_by_and;  // between clause k and k+1
  // True when the clauses hold for these values ("and" binding tighter than "or"): values[k] is
  // clause k's observable, or values[column[k]] with a column map (an observable named by several
  // clauses, sampled once). A clause k with unknown[k] does not hold, whatever its value (a value
  // of the last step, before the first step).
  bool holds(const std::vector<double>& values, const std::vector<size_t>* column = nullptr,
             const std::vector<bool>* unknown = nullptr) const;
  // Whether a term bounds t or step from above (<, <=, ==): its window of time may close
  // between two tests every 10 steps ("step == 57", "step > 56 and step < 58").
  bool has_window() const;
  // Whether a term's clauses on t and step all hold at (t, step) and not `ahead` steps of dt
  // later: a window that closes before the next regular test, in which the term must be tested
  // now. Where none does, the condition needs no other observable sampled before that test.
  bool window_closes(double t, int64_t step, double dt, int64_t ahead) const;
  // Whether a term that bounds t from above has its clauses on t and step holding at (t, step):
  // with an adaptive step, whose next values no dt foretells, such a term is tested at every step
  // while it may hold (a step grown by a fifth left "t >= 0.0207 and t <= 0.0255 and phi > 0"
  // between two tests).
  bool time_window_open(double t, int64_t step) const;
  // The end of the term that clause k begins: its clauses are [k, term_end(k)).
  size_t term_end(size_t k) const;
};

// How long `run` goes: N steps, a simulated time ("0.5s", "2e-3s"), until a condition, until
// the packing is static (the scene's criterion, run.static_*) or until the fluid is steady
// (run.steady_tol); or the scene's own length (`run` alone: to the scene's end step, stopping
// when static or steady if the scene says so).
struct RunLength {
  enum Kind { kSteps, kTime, kUntil, kStatic, kSteady, kScene } kind = kSteps;
  int64_t steps = 0;
  double time = 0;
  Condition until;
};
// From the arguments of `run` (or `start`); throws ParseError with the column of the bad word.
// A condition's comparisons need no blanks around them ("until t>=30").
RunLength parse_run_length(const std::vector<Token>& args);

// A list word (["grains", "chains"]) as its items, each with its column; any other word as itself.
// Throws ParseError.
std::vector<Token> expand_list(const Token& t);
// The arguments from `from` on with every list expanded.
std::vector<Token> expand_lists(const std::vector<Token>& args, size_t from = 0);

// A decimal number in full (no trailing garbage, no hexadecimal); nullopt otherwise.
std::optional<double> parse_number(std::string_view s);
// A whole number from `least` to kMaxRunSteps (steps, "every N"); nullopt otherwise.
std::optional<int64_t> parse_count(std::string_view s, int64_t least);
// The N of "every N": a whole number of steps from 1; throws ParseError at its column.
int64_t parse_every(const Token& t);

}  // namespace silt::shell
