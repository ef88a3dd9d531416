// The real interactive shell through a pseudo-terminal: line editing on GNU readline, Ctrl-C,
// completion, history across sessions, output that does not collide with the prompt.
#include <doctest/doctest.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "shell/shell_fixtures.hpp"
#include "support/files.hpp"
#include "support/scenes.hpp"

using silt::test::contains;
using silt::test::TempDir;

namespace {

// A `silt shell` on a pseudo-terminal, with HOME (the history file) and the working directory
// given: type lines, read what it prints.
class Terminal {
 public:
  // `inputrc`: readline's init file (INPUTRC), "" for none; `term`: TERM.
  Terminal(const std::string& scene, const std::string& home, const std::string& inputrc = "",
           const std::string& term = "xterm") {
    pid_ = forkpty(&fd_, nullptr, nullptr, nullptr);
    if (pid_ == 0) {
      setenv("HOME", home.c_str(), 1);
      if (inputrc.empty()) unsetenv("INPUTRC");
      else setenv("INPUTRC", inputrc.c_str(), 1);
      setenv("TERM", term.c_str(), 1);
      setenv("LC_ALL", "C.UTF-8", 1);  // readline reads multibyte characters
      if (chdir(home.c_str()) != 0) _exit(126);
      execl(silt::test::silt_binary().c_str(), "silt", "shell", scene.c_str(), "--threads", "2", nullptr);
      _exit(127);
    }
  }
  ~Terminal() { kill_now(); }
  // Written as the terminal takes it, its output read meanwhile (a long paste would otherwise
  // block on a full terminal while the shell blocks on drawing it).
  void type(const std::string& s) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    size_t at = 0;
    while (at < s.size() && std::chrono::steady_clock::now() < end) {
      pollfd p{fd_, POLLIN | POLLOUT, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      if (p.revents & POLLIN) {
        char buf[4096];
        const ssize_t n = read(fd_, buf, sizeof buf);
        if (n > 0) seen_.append(buf, n);
      }
      if (p.revents & POLLOUT) {
        const ssize_t n = write(fd_, s.data() + at, std::min<size_t>(s.size() - at, 1024));
        if (n > 0) at += static_cast<size_t>(n);
      }
      if (p.revents & (POLLHUP | POLLERR)) break;
    }
  }
  // Output until `marker` appears (or the timeout): "" when it did not.
  std::string read_until(const std::string& marker, double seconds = 10) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end && seen_.find(marker) == std::string::npos) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 50) > 0) {
        char buf[4096];
        const ssize_t n = read(fd_, buf, sizeof buf);
        if (n <= 0) break;
        seen_.append(buf, n);
      }
    }
    const auto at = seen_.find(marker);
    if (at == std::string::npos) return "";
    std::string out = seen_.substr(0, at + marker.size());
    seen_.erase(0, at + marker.size());
    return out;
  }
  int wait_exit() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // The terminal closed (a window shut, an ssh connection lost): the kernel sends SIGHUP.
  void hang_up() {
    ::close(fd_);
    fd_ = -1;
  }
  // As a crash would end it: no chance to write anything.
  void kill_now() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  int fd_ = -1;
  pid_t pid_ = -1;
  std::string seen_;
};

}  // namespace

TEST_CASE("the interactive shell: GNU readline, Ctrl-C pauses a run, tab completion, quit") {
  TempDir home;
  Terminal t(silt::test::scene_path("chute"), home.path());
  const std::string banner = t.read_until("silt[t=0]> ");
  REQUIRE(!banner.empty());
  // The rl_* symbols are GNU readline's, not those of the libedit that OSMesa's LLVM loads.
  CHECK(contains(banner, "(GNU readline "));
  CHECK_FALSE(contains(banner, "warning"));
  t.type("run 100000000\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  t.type("\x03");  // Ctrl-C
  CHECK(!t.read_until("paused: ").empty());
  CHECK(!t.read_until("]> ").empty());  // the prompt is back
  t.type("prin\tste\t\n");              // completes to "print step"
  // The command's output follows the line typed: readline does not draw the prompt again first
  // (the output would overwrite it from column 0: "step = 0]> ").
  const std::string shown = t.read_until("step = ");
  REQUIRE(!shown.empty());
  CHECK_FALSE(contains(shown.substr(shown.rfind("print step")), "silt["));
  CHECK(!t.read_until("silt[t=").empty());  // then the prompt, once
  t.type("nonsense\n");
  CHECK(!t.read_until("unknown command 'nonsense'").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE(
    "a closed terminal (SIGHUP) ends the shell as quit does: the background run stops, its file is whole, exit 129") {
  TempDir home;
  Terminal t(silt::test::scene_path("chute"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  t.type("stats st.csv every 20\nstart 1e9\n");
  const std::string csv = home.path() + "/st.csv";
  auto lines = [&] {
    const std::string text = silt::test::read_file(csv);
    return std::count(text.begin(), text.end(), '\n');
  };
  for (int i = 0; i < 400 && lines() < 5; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  t.hang_up();
  CHECK(t.wait_exit() == 129);
  const std::string rows = silt::test::read_file(csv);
  CHECK(std::count(rows.begin(), rows.end(), '\n') >= 5);
  CHECK(rows.back() == '\n');
}

TEST_CASE("history: each line is saved as it is entered, and the next session has it") {
  TempDir home;
  {
    Terminal t(silt::test::scene_path("collision_normal"), home.path());
    REQUIRE(!t.read_until("silt[t=0]> ").empty());
    t.type("run 7\n");
    REQUIRE(!t.read_until("done: 7 steps").empty());
    REQUIRE(!t.read_until("]> ").empty());
    t.kill_now();  // no clean exit: what is in the file was written line by line
  }
  CHECK(contains(silt::test::read_file(home / ".silt_history"), "run 7"));
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  t.type("\x1b[A\n");  // Up: the previous session's line
  CHECK(!t.read_until("done: 7 steps").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("tab completes file names only where a command takes a file") {
  TempDir home;
  std::ofstream(home / "zz_only_file.txt") << "x\n";
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  // hash takes no argument: nothing to complete, and no file name either.
  t.type("hash zz\t\n");
  const std::string stats = t.read_until("usage: hash");
  REQUIRE(!stats.empty());
  CHECK_FALSE(contains(stats, "zz_only_file"));
  t.type("set contact.friction zz\t\n");
  const std::string set = t.read_until("set contact.friction: ");  // the error, after the echo
  REQUIRE(!set.empty());
  CHECK_FALSE(contains(set, "zz_only_file"));
  // load takes a file: its name is completed.
  t.type("load zz\t\n");
  CHECK(!t.read_until("zz_only_file.txt").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("on a terminal, the key sequences that crash readline's callback interface do nothing") {
  TempDir home;
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  t.type(
      "\x12\x18"
      "a\x15");  // Ctrl-R, Ctrl-X, a: a segmentation fault in GNU readline 8.2; Ctrl-U clears the line
  t.type(
      "\x18(\n\n\x18)\x18"
      "e\x15");  // a keyboard macro holding newlines, played
  // A character search (Ctrl-]) for an Escape, then a key: a null pointer read in readline 8.2;
  // the start of a bracketed paste (Escape [200~), whose end, if input stopped before it,
  // overflowed readline's buffer: both unbound now.
  t.type("\x1d\x1b\x01\x15\x1b[200~\x15");
  t.type("print step\n");
  CHECK(!t.read_until("step = 0").empty());
  // A line killed and yanked back forty times, four rounds: 26 million characters, minutes in
  // readline; held at 4,096 bytes now.
  std::string yanks = "abcdefghij";
  for (int round = 0; round < 4; ++round) yanks += "\x01\x0b" + std::string(40, '\x19');
  t.type(yanks + "\x15print t\n");
  CHECK(!t.read_until("t = 0").empty());
  // The non-incremental history search (Meta-p), in which readline 8.2 frees undo records twice
  // (tests/fuzz/crashes/noninc_search_undo.keys, replayed by the test script), does nothing: the
  // keys after it are typed into the line.
  t.type("abc\x1bpx\n");
  CHECK(!t.read_until("unknown command 'abcx'").empty());
  // Vi mode (Meta-Ctrl-J), an escape sequence with a number cut by a byte above 127 or a control
  // character: a null pointer read in readline 8.2's callback interface. Then 'i' to insert.
  t.type("\x1b\n\x1b[5\xae\x1b[1;5\x01iprint t\n");
  CHECK(!t.read_until("t = 0").empty());
  // The same sequences cut by p, P or v (vi's put and the editing-mode key): the same null pointer
  // read, in the real shell too (tests/fuzz/crashes/vi_escape_prefix_put.keys).
  t.type("\x1b[5p\x1b[1;5P\x1b[2v\x1b[6piprint t\n");
  CHECK(!t.read_until("t = 0").empty());
  // Still in vi mode: bytes that are no UTF-8 character, then `w` on them (readline looped
  // forever), the line then changed whole (cc); a character of two bytes reaches the command whole.
  t.type("save a.ckp\xff\xbf\x1bwcc");
  t.type("print t\xc3\xa9\n");
  CHECK(!t.read_until("unknown observable 't\xc3\xa9'").empty());
  // Still in vi mode: a line yanked (0y$) and put back with a count (999p) three times, then the
  // put redone with a count (999.): one reallocation of the line per copy, minutes and gigabytes
  // in readline 8.2 once the line is long; the counts of both are held at 16 now, and the line
  // cut back to 4,096 bytes at the next key.
  std::string puts = "abcdefgh\x1b";
  for (int k = 0; k < 3; ++k) puts += "0y$999p";
  for (int k = 0; k < 8; ++k) puts += "999.";
  t.type(puts + "ccprint t\n");
  CHECK(!t.read_until("t = 0", 30).empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("vi mode on an edited history line: Escape keeps the undo records the history holds") {
  TempDir home;
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  t.type("3\n");
  REQUIRE(!t.read_until("unknown command '3'").empty());
  // Up, `a`, vi mode (Meta-Ctrl-J), Up, Escape, `h`: readline 8.2 freed the line's undo records at
  // the first Escape while the history entry kept them (tests/fuzz/crashes/vi_history_undo.keys).
  // Then the line entered, the history walked over both lines, the first entered again.
  t.type("\x1b[Aa\x1b\n\x1b[A\x1bh\n");
  CHECK(!t.read_until("unknown command '3a'").empty());
  t.type("\x1b[A\x1b[A\x1b[B\x1b[A\n");
  CHECK(!t.read_until("unknown command '3'").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE(
    "a failed history search on an edited history line, then Up at the first entry: its undo records stay its own") {
  TempDir home;
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  t.type("3\n");
  REQUIRE(!t.read_until("unknown command '3'").empty());
  // Ctrl-P, `a`, Page Up (a history search that finds nothing), Up on the first entry: readline
  // 8.2 saved the line with the entry's undo records and freed them with it while the entry kept
  // them (tests/fuzz/crashes/history_search_saved_line.keys). Then the line entered, the first
  // entry recalled and its edit undone (Ctrl-_), which read the freed records.
  t.type(std::string("\x10") + "a\x1b[5~\x1b[A\n");
  CHECK(!t.read_until("unknown command '3a'").empty());
  t.type("\x1b[A\x1b[A\x1f\n");
  CHECK(!t.read_until("unknown command '3'").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("a count ended by Enter enters the line at once, in emacs and in vi mode") {
  TempDir home;
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  // readline 8.2's callback interface handed such a line over only at the next key, after running
  // that key on the finished line (tests/fuzz/crashes/vi_count_enter_subst.keys).
  t.type(
      "emacs\x1b"
      "2\n");  // Meta-2, Enter
  CHECK(!t.read_until("unknown command 'emacs'").empty());
  t.type(
      "\x1b\nvi\x1b"
      "1\n");  // Meta-Ctrl-J (vi mode), Escape, 1, Enter
  CHECK(!t.read_until("unknown command 'vi'").empty());
  t.type(
      "sx\x1b"
      "0fx\n");  // the next line starts in insert mode; then a forward search
  CHECK(!t.read_until("unknown command 'sx'").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("vi's redo of an operator left without a motion keeps the line whole") {
  TempDir home;
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  // vi mode (Meta-Ctrl-J), `cc` (recorded as the motion c), `d.` (a delete left without a motion),
  // then `.`: readline 8.2 ran c as the motion of d, which emptied the line and left its end past
  // the NUL; this line was lost, and on others `fx` looped forever
  // (tests/fuzz/crashes/vi_redo_cross_operator.keys).
  t.type(
      "\x1b\nprint t\x1b"
      "0ccprint step\x1b"
      "0d..fx\n");
  CHECK(!t.read_until("step = 0").empty());
#if !defined(SILT_ASAN)
  // A redo of an operator with its own motion still repeats it: `dw`, then `.` deletes a word.
  // (Not in the sanitizer build: readline 8.2 leaks 3 bytes in this redo, which fails the exit
  // code; the leak is readline's, the same before the refusal above.)
  t.type(
      "print a b step\x1b"
      "0wdw.\n");
  CHECK(!t.read_until("step = 0").empty());
#endif
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("vi's word motion ends on a line with a broken character or one of no width, typed or recalled") {
  TempDir home;
  // A history line of an earlier session with U+FFFF at its end (wcwidth -1).
  std::ofstream(home / ".silt_history") << "print t?\xef\xbf\xbf\n";
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  // Recalled from the history: vi mode, Escape, k, the point put on the '?' before U+FFFF (0, 7l),
  // `w`: readline 8.2 went back and forth between the last two characters forever. Then the line
  // changed into one that runs.
  t.type(
      "\x1b\n\x1bk07lw\x1b"
      "0Cprint step\n");
  CHECK(!t.read_until("step = 0").empty());
  // Typed: \xc3 cut short by \xd9, \xd9 by U+FFFF, Escape (back onto the last character), `w`:
  // the same, the byte that cut the first short having reached the line unchecked ("?", "\xd9",
  // U+FFFF).
  t.type(
      "print t\xc3\xd9\xef\xbf\xbf\x1bw\x1b"
      "0Cprint step\n");
  CHECK(!t.read_until("step = 0").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("a count's long insertion is drawn wrapped, and a dumb terminal reads plain lines") {
  TempDir home;
  // readline 8.2 scrolling the line sideways (an inputrc's horizontal-scroll-mode, or a terminal
  // that cannot move the cursor up) read past its display buffer after Meta-1000 and a key
  // (AddressSanitizer: heap-buffer-overflow in rl_redisplay): the mode is turned off after the
  // inputrc is read, and TERM=dumb reads plain lines.
  std::ofstream(home / "inputrc") << "set horizontal-scroll-mode on\n";
  {
    Terminal t(silt::test::scene_path("collision_normal"), home.path(), home / "inputrc");
    REQUIRE(!t.read_until("silt[t=0]> ").empty());
    t.type(
        "\x1b"
        "1000b");
    t.type("\x15print step\n");
    const std::string shown = t.read_until("step = 0");
    CHECK(!shown.empty());
    // Wrapped, all 1,000 are drawn; scrolled sideways, a screen's width of them.
    CHECK(std::count(shown.begin(), shown.end(), 'b') >= 1000);
    t.type("quit\n");
    CHECK(t.wait_exit() == 0);
  }
  Terminal t(silt::test::scene_path("collision_normal"), home.path(), home / "inputrc", "dumb");
  REQUIRE(!t.read_until("loaded").empty());
  CHECK(!t.read_until("silt[t=0]> ").empty());  // a prompt all the same
  t.type(
      "\x1b"
      "1000b\n");  // a line as any other, refused
  CHECK(!t.read_until("control character").empty());
  CHECK(!t.read_until("silt[t=0]> ").empty());
  t.type("print st\x03");  // Ctrl-C: the terminal drops the line, and a new prompt follows
  CHECK(!t.read_until("\nsilt[t=0]> ").empty());
  t.type("print step\n");
  CHECK(!t.read_until("step = 0").empty());
  // A background run's messages on lines of their own, then the prompt again.
  t.type("start 20\n");
  CHECK(!t.read_until("\nsilt[t=").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
  CHECK(contains(silt::test::read_file(home / ".silt_history"), "print step\nstart 20\nquit\n"));
}

TEST_CASE("a long line is cut to 4 KiB at a character: vi's motions cross it promptly, a long paste's Enter is kept") {
  TempDir home;
  Terminal t(silt::test::scene_path("collision_normal"), home.path());
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  // "(((" then five times Meta-1000 and a character of two bytes (10,003 bytes), entered: cut at
  // the next key to 4,095 bytes, as byte 4,096 is the second of a character.
  const std::string meta_1000_e = std::string("\x1b") + "1000\xc3\xa9";
  std::string keys = "(((";
  for (int k = 0; k < 5; ++k) keys += meta_1000_e;
  std::string cut = "(((";
  for (int k = 0; k < 2046; ++k) cut += "\xc3\xa9";
  t.type(keys + "\n");
  CHECK(!t.read_until("unknown command '" + cut + "' (help").empty());
  // Forty such insertions, then vi mode (Meta-Ctrl-J) and the bracket match (%) ten times:
  // readline 8.2 finds each character boundary from the line's start, so on the 65,536 bytes the
  // line was held at before, the ten took 46 s.
  keys = "(";
  for (int k = 0; k < 40; ++k) keys += meta_1000_e;
  t.type(keys +
         "\x1b\n\x1b"
         "0%%%%%%%%%%$bbbwwwe0999w999bcc");
  t.type("print t\n");
  CHECK(!t.read_until("t = 0", 20).empty());
  // A paste of 70,000 characters and its Enter: the line entered is the first 4,096. Readline takes
  // the paste a key at a time (1.5 s in the Release build, 4 s under the sanitizers alone, more
  // with another test beside it), so this bound is not about promptness.
  t.type(std::string(70000, 'x') + "\nprint step\n");
  CHECK(!t.read_until("unknown command '" + std::string(4096, 'x') + "' (help", 40).empty());
  CHECK(!t.read_until("step = 0").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("commands that crash readline's callback interface do nothing under any key an inputrc gives them") {
  TempDir home;
  // Every keymap: emacs, its Meta and Ctrl-X maps, vi insertion and vi command (movement); keys
  // that are prefixes of others; and the init file read again (Ctrl-X Ctrl-R) binds them anew.
  std::ofstream(home / "inputrc") << "\"\\C-t\": reverse-search-history\n"
                                     "\"\\eq\": forward-search-history\n"
                                     "\"\\C-xq\": start-kbd-macro\n"
                                     "\"\\C-xw\": end-kbd-macro\n"
                                     "\"\\C-o\": call-last-kbd-macro\n"
                                     "\"\\C-g\\C-g\": reverse-search-history\n"
                                     "set keymap vi-insert\n"
                                     "\"\\C-t\": reverse-search-history\n"
                                     "set keymap vi-command\n"
                                     "\"s\": forward-search-history\n"
                                     "\"\\C-t\": call-last-kbd-macro\n";
  Terminal t(silt::test::scene_path("collision_normal"), home.path(), home / "inputrc");
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  // Ctrl-T, Ctrl-X, a: a segmentation fault in GNU readline 8.2 with Ctrl-T bound to
  // reverse-search-history; Ctrl-U clears the line.
  t.type(
      "\x14\x18"
      "a\x15");
  t.type(
      "\x1bq\x18"
      "a\x15\x07\x07\x18"
      "a\x15");                           // Meta-q, the sequence Ctrl-G Ctrl-G
  t.type("\x18qprint t\n\x18w\x0f\x15");  // a keyboard macro recorded and played
  CHECK(!t.read_until("t = 0").empty());
  t.type(
      "\x18\x12\x14\x18"
      "a\x15");                // the inputrc read again (Ctrl-X Ctrl-R), then Ctrl-T
  t.type("step\x01print \n");  // ordinary line editing stays: Ctrl-A to the line's beginning
  CHECK(!t.read_until("step = 0").empty());
  // Vi mode (Meta-Ctrl-J): Ctrl-T in insertion mode; Escape, then s and Ctrl-T in command mode;
  // cc changes the whole line.
  t.type(
      "\x1b\n\x14\x18"
      "a\x1bs\x14"
      "ccprint dt\n");
  CHECK(!t.read_until("dt = ").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
}

TEST_CASE("without a terminal the shell reads plain lines: control characters are part of them") {
  TempDir dir;
  const std::string bin = silt::test::silt_binary();
  auto shell = [&](const std::string& input) {
    std::ofstream(dir / "in.txt", std::ios::binary) << input;
    const std::string cmd = bin + " shell " + silt::test::scene_path("collision_normal") + " < " + (dir / "in.txt") +
                            " > " + (dir / "out.txt") + " 2>&1";
    const int status = std::system(cmd.c_str());
    return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, silt::test::read_file(dir / "out.txt"));
  };
  // Lines from a file go on after an error, and the exit code is the highest of the errors'
  // (it was 0 whatever failed): none here.
  auto [code, out] = shell("print step\nrun 3\n");
  CHECK(code == 0);
  CHECK(contains(out, "done: 3 steps"));
  std::tie(code, out) = shell("print nothing\nsave " + (dir / "nodir/a.ckpt") + "\nprint step\n");
  CHECK(code == 4);
  CHECK(contains(out, "step = 0"));
  // Ctrl-R, Ctrl-X and a letter, as `printf '\x12\x18a' | silt shell` sends them.
  std::tie(code, out) = shell(
      "\x12\x18"
      "a");
  CHECK(code == 2);
  CHECK(contains(out, "control character"));
  // Ctrl-A is not "beginning of line": the line is not "xhelp".
  std::tie(code, out) = shell("help\x01x\nprint step\n");
  CHECK(code == 2);
  CHECK(contains(out, "control character"));
  CHECK_FALSE(contains(out, "xhelp"));
  CHECK(contains(out, "step = 0"));
  // Random bytes: never a crash nor a hang.
  std::string noise;
  uint64_t x = 88172645463325252ull;
  for (int k = 0; k < 20000; ++k) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    noise.push_back(static_cast<char>(x & 0xff));
  }
  std::tie(code, out) = shell(noise);
  CHECK(code == 2);
  // A line of 3 MiB (as `silt shell < /dev/zero` reads): refused, and the next line runs. The whole
  // of it was kept and searched again from its start after every read (300 MB of zeros: minutes).
  std::tie(code, out) = shell(std::string(3 << 20, 'x') + "\nprint step\n");
  CHECK(code == 2);
  CHECK(contains(out, "a line longer than 1048576 bytes: ignored"));
  CHECK(contains(out, "step = 0"));
}
