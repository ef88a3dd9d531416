#include "shell/readline_setup.hpp"

#include <readline/history.h>
#include <readline/readline.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cwchar>
#include <string>
#include <utility>
#include <vector>

// readline 8.2's state of a count being read (rlprivate.h, not installed): NUM_READONE makes the key
// that ends the count come back as the next key read, as universal-argument does in the callback
// interface. See ends_count_accepting_line and guarded_getc.
extern "C" int _rl_argcxt;
// readline 8.2's copy of the line being typed while the history is walked (misc.c, not installed).
extern "C" HIST_ENTRY* _rl_saved_line_for_history;

namespace silt::cli {
namespace {

const shell::Session* g_completing = nullptr;
std::vector<std::string> g_matches;

char* completion_generator(const char*, int state) {
  static size_t next = 0;
  if (state == 0) next = 0;
  if (next < g_matches.size()) return strdup(g_matches[next++].c_str());
  return nullptr;
}

char** completion(const char* text, int, int) {
  if (!g_completing) return nullptr;
  const std::string before(rl_line_buffer, rl_line_buffer + (rl_point - std::strlen(text)));
  const auto words = g_completing->complete(before, text);
  if (!words) return nullptr;        // a file name: readline's own completion
  rl_attempted_completion_over = 1;  // no file names where the command takes none
  g_matches = *words;
  return rl_completion_matches(text, completion_generator);
}

// In a multibyte (UTF-8) locale, readline 8.2's vi motions do not move over a byte that is no
// character, nor over a character that has no width on a terminal (wcwidth -1: U+FFFF, the C1
// controls): `w` on "\xff\xbf" loops forever, and on "?" then U+FFFF at the line's end it goes
// back and forth between the two. A character's bytes are read together (a terminal sends them
// together), and bytes that make no printable character become '?'. One character from its first
// byte: its bytes, or "?"; `cut` is the byte that cut it short (EOF if none).
std::string read_character(FILE* stream, int lead, int& cut) {
  cut = EOF;
  const int more = lead >= 0xc2 && lead <= 0xdf   ? 1
                   : lead >= 0xe0 && lead <= 0xef ? 2
                   : lead >= 0xf0 && lead <= 0xf4 ? 3
                                                  : -1;
  if (more < 0) return "?";  // a continuation byte alone, or a byte no UTF-8 character begins with
  std::string bytes(1, static_cast<char>(lead));
  for (int k = 1; k <= more; ++k) {
    const int b = rl_getc(stream);
    if (b < 0x80 || b > 0xbf) {
      cut = b;
      return "?";
    }
    bytes.push_back(static_cast<char>(b));
  }
  std::mbstate_t state{};
  wchar_t w = 0;
  if (std::mbrtowc(&w, bytes.data(), bytes.size(), &state) != bytes.size() || wcwidth(w) < 0) return "?";
  return bytes;
}

// The key readline reads for a byte above 127: the first byte of what read_character made, the
// others handed back to readline as pending input. The byte that cut a character short is read
// as the next character, through the same check (handed back unchecked, a lead byte reached the
// line alone); a run of such bytes is read up to 64 bytes, the byte that cuts the last one short
// then a '?' of its own (readline's pending input holds 512). keep_printable_line mends what other
// paths bring (a history file written in another encoding, a line's edits).
int utf8_checked(FILE* stream, int lead) {
  int cut = EOF;
  std::string typed = read_character(stream, lead, cut);
  while (cut != EOF) {
    if (cut < 0x80 || typed.size() >= 64) {
      typed.push_back(cut < 0x80 ? static_cast<char>(cut) : '?');
      break;
    }
    int next = EOF;
    typed += read_character(stream, cut, next);
    cut = next;
  }
  for (size_t k = 1; k < typed.size(); ++k) rl_stuff_char(static_cast<unsigned char>(typed[k]));
  return static_cast<unsigned char>(typed[0]);
}

// Every byte of the line that begins no whole character, and each byte of a character of no
// width, becomes '?', in place (the line keeps its length, so the point, the mark and the undo
// records keep their places).
void keep_printable_line() {
  if (MB_CUR_MAX == 1 || !rl_line_buffer) return;
  for (int i = 0; i < rl_end;) {
    if (static_cast<unsigned char>(rl_line_buffer[i]) < 0x80) {
      ++i;
      continue;
    }
    std::mbstate_t state{};
    wchar_t w = 0;
    const size_t n = std::mbrtowc(&w, rl_line_buffer + i, static_cast<size_t>(rl_end - i), &state);
    if (n == 0 || n > static_cast<size_t>(rl_end - i)) {  // (size_t)-1 and -2: no whole character
      rl_line_buffer[i++] = '?';
      continue;
    }
    if (wcwidth(w) < 0) std::memset(rl_line_buffer + i, '?', n);
    i += static_cast<int>(n);
  }
}

// A count (Meta and digits, or digits in vi command mode) is held at kMaxCount: readline takes up
// to 1,000,000, and a character typed after it was inserted that many times (36 s in the fuzz
// build, found as a timeout).
constexpr int kMaxCount = 1000;

// A line is held at kMaxLine bytes: a killed line yanked back many times, killed again and yanked
// again grows geometrically (four rounds of Ctrl-A Ctrl-K and forty Ctrl-Y took minutes; found as
// a libFuzzer timeout). Before each key, a longer line is cut back, unless a key sequence, a count
// or a search is being read. The cut is an edit as any other, which undo takes back: freeing the
// line's undo list instead left history entries holding freed records, as readline 8.2 forgets
// only the entries that point at the list's head, while a history line edited, left and recalled
// points inside it (double frees the fuzzer found, through the history and vi's search).
// 4 KiB, not more: in a multibyte locale readline 8.2 finds a character boundary by reading the
// line from its start, so a motion over the line costs its length squared: vi's bracket match (%)
// repeated on a line of 64 KiB took three minutes in the fuzz build (a libFuzzer timeout), one
// second at 4 KiB. The cut ends at a character's first byte, so that the line keeps whole
// characters (vi's word motions looped forever on a byte that is none, above).
constexpr int kMaxLine = 1 << 12;

// The first byte of the character that byte kMaxLine of `line` belongs to.
int character_cut(const char* line) {
  int cut = kMaxLine;
  while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xc0) == 0x80) --cut;
  return cut;
}

void hold_line_length() {
  if (rl_end <= kMaxLine || RL_ISSTATE(RL_STATE_MULTIKEY | RL_STATE_NUMERICARG | RL_STATE_ISEARCH | RL_STATE_NSEARCH |
                                       RL_STATE_SEARCH | RL_STATE_CHARSEARCH | RL_STATE_VIMOTION))
    return;
  rl_delete_text(character_cut(rl_line_buffer), rl_end);
  rl_point = std::min(rl_point, rl_end);
  rl_mark = std::min(rl_mark, rl_end);
  rl_ding();
}

// vi's put (p, P) and redo (.) insert a text count times within one key, where the line's cut
// cannot reach: readline 8.2 grows the line by one reallocation per copy, so a count of 999 on a
// line of 64 KiB took minutes and gigabytes (a libFuzzer out-of-memory). Their count is held at
// kMaxRepeat; a redo of a put reaches the put through its key, and is held there.
constexpr int kMaxRepeat = 16;

int held_vi_put(int count, int key) { return rl_vi_put(std::min(count, kMaxRepeat), key); }

// vi's redo (.) of an operator (d, c, y) in readline 8.2 runs it with the motion of the last
// operator that had one, whichever it was: after `cc` (recorded as the motion c) a `d` left
// without a motion (`d` Escape, `d.`) is the command redone, and `.` dispatches `c` as the motion
// of `d`. The change inside the delete empties the line, and the delete then restores the line's
// old end: rl_end past a NUL, on which the forward character search (vi's f, t) loops forever
// (vi mode, `1` Escape `S` Escape `p` `d..` `fx`: silt's shell at full CPU until killed; found by
// the terminal fuzz target's check of the line, tests/fuzz/crashes/vi_redo_cross_operator.keys).
// A motion read by the operator itself may be a redo too (an operator run from an Escape
// sequence's fallback reads it so), which runs the last command inside the operator. readline
// runs an operator or a redo while an operator runs only on such paths (`dd` and its redo take
// another): they are refused, and the outer operator then fails for want of a motion, as vi's
// does. The watch ends at the next command key read (guarded_getc): an operator left by readline's
// longjmp must not leave every later one refused.
bool g_operator_running = false;

// Whether a redo or an operator is refused here (it rings the bell if so).
bool refused_inside_operator() {
  if (g_operator_running) rl_ding();
  return g_operator_running;
}

int held_vi_redo(int count, int key) {
  if (refused_inside_operator()) return 1;
  return rl_vi_redo(std::min(count, kMaxRepeat), key);
}

template <rl_command_func_t* Operator>
int single_operator(int count, int key) {
  if (refused_inside_operator()) return 1;
  g_operator_running = true;
  const int r = Operator(count, key);
  g_operator_running = false;
  return r;
}

// readline 8.2's callback interface does not hand over a line accepted by the key that ends a
// count (vi: `1` Enter; emacs: Meta-1 Enter): rl_callback_read_char returns from the count's branch
// without looking at rl_done, so the line waits for the next key, which then runs on the finished
// line before it is handed over (vi mode, `st`, Escape, `1`, Enter, `s`: found by the terminal
// fuzz target, tests/fuzz/crashes/vi_count_enter_subst.keys). Such a key is handed back to
// readline as the next key to read, with the count kept (readline's own NUM_READONE, which
// universal-argument uses in this interface): readline then reads it as any key, and the line
// goes to the handler at once. Whether c is such a key; guarded_getc sets readline's state.
bool ends_count_accepting_line(int c) {
  if (!RL_ISSTATE(RL_STATE_NUMERICARG) || c < 0 || c >= KEYMAP_SIZE - 1) return false;
  const int plain = c & 0x7f;
  if (std::isdigit(plain) || plain == '-') return false;  // digits and the sign continue the count
  const KEYMAP_ENTRY& e = rl_get_keymap()[c];
  if (e.type != ISFUNC) return false;
  for (rl_command_func_t* accepts : {rl_newline, rl_vi_eof_maybe, rl_operate_and_get_next, rl_insert_comment})
    if (e.function == accepts) return true;
  return false;
}

// readline 8.2 keeps the line being typed, with its undo list, while the user walks the history
// (the saved line), and gives the history entry on show the undo list of its edits. A failed
// history search (Page Up's history-search-backward) drops the saved line but leaves the walk on
// an entry; the next history command then saves the edited entry's line with that entry's undo
// list: two owners of one list. previous-history on the first entry (or beginning-of-history
// there) then frees the list with the saved line, and the entry keeps the freed records, freed
// again when the history is cleared, used when the entry is recalled and undone
// (tests/fuzz/crashes/history_search_saved_line.keys); a saved line that lives on frees them at
// the next line instead. A walk on an entry always has a saved line here, with no undo list of its
// own: the entry's stays the entry's.
void keep_saved_line() {
  if (_rl_saved_line_for_history || where_history() >= history_length) return;
  rl_maybe_save_line();
  _rl_saved_line_for_history->data = nullptr;
}

// The keys as readline reads them, with two of its crashes kept away and counts bounded. In vi
// mode, an escape sequence that bound ones begin with and that ends in a number so far ("\e[5",
// a prefix of Page Up's "\e[5~"; "\e[1;5") makes readline 8.2's callback interface read a null
// pointer when the next byte does not continue it and is p, P or v (readline falls back to Escape,
// `[`, the number as a count and that command) or a control character, DEL or a byte above 127.
// Such a byte ends the sequence as an Escape does (the sequence and the byte are dropped, and the
// Escape enters command mode): after a number, any byte that leaves the bound sequences; anywhere
// in the sequence, a byte that is not printable ASCII. readline's own record of the sequence read
// so far is the reference (rl_executing_keyseq). Escaping more than this (any byte that leaves a
// bound sequence, "\e[s" too) reached another of readline's double frees of undo records within
// minutes of fuzzing. Bytes above 127: utf8_checked.
int guarded_getc(FILE* stream) {
  hold_line_length();
  keep_printable_line();
  // vi's first Escape in a line frees the line's undo list (so that U reverts only to there), and
  // readline 8.2 then forgets a history entry's pointer into that list only when it points at its
  // head: a history line recalled and edited, vi mode, Up, Escape left an entry holding freed
  // records (a double free when the history is cleared; tests/fuzz/crashes/vi_history_undo.keys).
  // The line counts as having entered command mode already: nothing is freed, and U reverts the
  // whole line.
  RL_SETSTATE(RL_STATE_VICMDONCE);
  keep_saved_line();
  if (RL_ISSTATE(RL_STATE_READCMD)) g_operator_running = false;  // a command's first key
  const int c = rl_getc(stream);
  if (RL_ISSTATE(RL_STATE_NUMERICARG) && rl_numeric_arg > kMaxCount) rl_numeric_arg = kMaxCount;
  if (ends_count_accepting_line(c)) {
    constexpr int kNumReadOne = 0x04;  // rlprivate.h
    _rl_argcxt |= kNumReadOne;         // c comes back as the next key read, the count kept
    return c;
  }
  if (RL_ISSTATE(RL_STATE_MULTIKEY) && rl_editing_mode == 0 && c != EOF && rl_key_sequence_length >= 1 &&
      rl_executing_keyseq[0] == '\033') {
    if (c < 0x20 || c > 0x7e) return '\033';
    if (rl_key_sequence_length >= 2 &&
        std::isdigit(static_cast<unsigned char>(rl_executing_keyseq[rl_key_sequence_length - 1]))) {
      std::string sequence(rl_executing_keyseq, static_cast<size_t>(rl_key_sequence_length));
      sequence.push_back(static_cast<char>(c));
      int type = ISFUNC;
      if (!rl_function_of_keyseq_len(sequence.data(), sequence.size(), rl_get_keymap(), &type)) return '\033';
    }
  }
  if (c >= 0x80 && MB_CUR_MAX > 1) return utf8_checked(stream, c);
  return c;
}

// The commands whose paths through readline 8.2's callback interface crash or hang: the
// incremental history searches (Ctrl-R, Ctrl-S by default), the keyboard macros (Ctrl-X ( ) e),
// the character searches (Ctrl-], Meta-Ctrl-]: an Escape as the character sought, then any key,
// reads a null pointer), the bracketed paste (Escape [200~: input that ends inside the paste
// overflows its buffer) and vi's history search (/ ? n N: a line found, edited, left with k and
// recalled with j, edited again and left, leaves a history entry holding freed undo records,
// freed again when the history is cleared) and the other non-incremental history searches, whose
// code vi's shares (Meta-p, Meta-n: `5`, Ctrl-O, Ctrl-P, Meta-p, Enter, `a`, Ctrl-P frees undo
// records twice when the line is reverted). They are unbound by function, not by key: a user's
// inputrc may give them any key. (The vi mode's character searches, f F t T, do not crash.)
bool crashes_readline(rl_command_func_t* f) {
  for (rl_command_func_t* bad :
       {rl_reverse_search_history, rl_forward_search_history, rl_start_kbd_macro, rl_end_kbd_macro,
        rl_call_last_kbd_macro, rl_char_search, rl_backward_char_search, rl_bracketed_paste_begin, rl_vi_search,
        rl_vi_search_again, rl_noninc_forward_search, rl_noninc_reverse_search, rl_noninc_forward_search_again,
        rl_noninc_reverse_search_again})
    if (f == bad) return true;
  return false;
}

void guard_keymaps();

// Re-reading the inputrc (Ctrl-X Ctrl-R) binds and sets what it says again: the guard follows it.
int reread_init_file(int count, int key) {
  const int r = rl_re_read_init_file(count, key);
  guard_keymaps();
  return r;
}

// What a binding of f becomes: nothing for a crashing command, silt's version of a command it
// wraps, f itself otherwise.
rl_command_func_t* guarded(rl_command_func_t* f) {
  if (crashes_readline(f)) return nullptr;
  const std::pair<rl_command_func_t*, rl_command_func_t*> wrapped[] = {
      {rl_re_read_init_file, reread_init_file},
      {rl_vi_put, held_vi_put},
      {rl_vi_redo, held_vi_redo},
      {rl_vi_delete_to, single_operator<rl_vi_delete_to>},
      {rl_vi_change_to, single_operator<rl_vi_change_to>},
      {rl_vi_yank_to, single_operator<rl_vi_yank_to>}};
  for (const auto& [from, to] : wrapped)
    if (f == from) return to;
  return f;
}

// Every binding of `map` and the keymaps under it guarded (a prefix key, "\C-x" or Escape, leads
// to another keymap; ANYOTHERKEY, the last entry, holds what a prefix key did alone before a
// longer sequence was bound under it).
void guard_keymap(Keymap map, std::vector<Keymap>& seen) {
  if (!map || std::find(seen.begin(), seen.end(), map) != seen.end()) return;
  seen.push_back(map);
  for (int k = 0; k < KEYMAP_SIZE; ++k) {
    KEYMAP_ENTRY& e = map[k];
    if (e.type == ISKMAP) guard_keymap(reinterpret_cast<Keymap>(e.function), seen);  // readline stores it so
    else if (e.type == ISFUNC) e.function = guarded(e.function);
  }
}

void guard_keymaps() {
  // Without its paste command, the terminal is not asked to mark pastes: a paste arrives as typed.
  rl_variable_bind("enable-bracketed-paste", "off");
  // The line scrolled sideways instead of wrapped reads past readline 8.2's display buffer after a
  // count's insertion of about 1,000 characters (heap-buffer-overflow in rl_redisplay): wrapped.
  rl_variable_bind("horizontal-scroll-mode", "off");
  std::vector<Keymap> seen;
  for (Keymap map :
       {emacs_standard_keymap, emacs_meta_keymap, emacs_ctlx_keymap, vi_insertion_keymap, vi_movement_keymap})
    guard_keymap(map, seen);
}

}  // namespace

size_t held_line_end(const char* line) {
  const size_t n = std::strlen(line);
  return n <= static_cast<size_t>(kMaxLine) ? n : static_cast<size_t>(character_cut(line));
}

void guard_readline_keys() {
  guard_keymaps();
  rl_bind_keyseq("\\e[5~", rl_history_search_backward);  // Page Up: history with this prefix
  rl_bind_keyseq("\\e[6~", rl_history_search_forward);
  rl_getc_function = guarded_getc;
}

void install_completion(const shell::Session* session) {
  g_completing = session;
  rl_attempted_completion_function = session ? completion : nullptr;
}

}  // namespace silt::cli
