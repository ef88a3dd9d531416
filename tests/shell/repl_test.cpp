// The real interactive shell through a pseudo-terminal, and scripts through `silt play`.
#include <doctest/doctest.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "silt/io.hpp"
#include "support/scenes.hpp"

namespace {

// A `silt shell` on a pseudo-terminal: type lines, read what it prints.
class Terminal {
 public:
  explicit Terminal(const std::string& scene) {
    pid_ = forkpty(&fd_, nullptr, nullptr, nullptr);
    if (pid_ == 0) {
      setenv("HOME", "/tmp", 1);  // history file
      execl(silt::test::silt_binary().c_str(), "silt", "shell", scene.c_str(), "--threads", "2", nullptr);
      _exit(127);
    }
  }
  ~Terminal() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  void type(const std::string& s) { (void)!write(fd_, s.data(), s.size()); }
  // Output until `marker` appears (or the timeout).
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

 private:
  int fd_ = -1;
  pid_t pid_ = -1;
  std::string seen_;
};

std::string run_play(const std::string& script_text, const std::string& flags, int* code) {
  std::ofstream("play_test.silt") << script_text;
  const std::string cmd = silt::test::silt_binary() + " play play_test.silt " + flags + " 2>&1";
  std::FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int status = pclose(p);
  *code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

}  // namespace

TEST_CASE("the interactive shell: commands, Ctrl-C pauses a run, tab completion, history, quit") {
  std::remove("/tmp/.silt_history");
  Terminal t(silt::test::scene_path("chute"));
  REQUIRE(!t.read_until("silt[t=0]> ").empty());
  t.type("run 100000000\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  t.type("\x03");  // Ctrl-C
  CHECK(!t.read_until("paused: ").empty());
  CHECK(!t.read_until("]> ").empty());  // the prompt is back
  t.type("prin\tste\t\n");  // completes to "print step"
  CHECK(!t.read_until("step = ").empty());
  t.type("nonsense\n");
  CHECK(!t.read_until("unknown command 'nonsense'").empty());
  t.type("quit\n");
  CHECK(t.wait_exit() == 0);
  std::ifstream history("/tmp/.silt_history");
  std::stringstream h;
  h << history.rdbuf();
  CHECK(h.str().find("print step") != std::string::npos);
}

TEST_CASE("silt play: echoes each command with its line, stops at the first error with SCRIPT:LINE") {
  int code = -1;
  const std::string script = "# a script\nload " + silt::test::scene_path("collision_normal") +
                             "\nrun 100\nprint step\nprnt t\nrun 100\n";
  std::string out = run_play(script, "", &code);
  CHECK(code == 2);
  CHECK(out.find("play_test.silt:3> run 100") != std::string::npos);
  CHECK(out.find("step = 100") != std::string::npos);
  CHECK(out.find("play_test.silt:5: unknown command 'prnt'; did you mean 'print'?") != std::string::npos);
  CHECK(out.find("play_test.silt:6>") == std::string::npos);
  out = run_play(script, "--keep-going", &code);
  CHECK(code == 2);
  CHECK(out.find("play_test.silt:6> run 100") != std::string::npos);
  out = run_play("load " + silt::test::scene_path("collision_normal") + "\nrun 10\n", "", &code);
  CHECK(code == 0);
  run_play("", "", &code);
  CHECK(code == 0);
  std::remove("play_test.silt");
}

TEST_CASE("the shipped example script plays") {
  const std::string cmd = "cd " + std::string(SILT_SOURCE_DIR) + " && " + silt::test::silt_binary() +
                          " play scenes/steer_and_save.silt > /dev/null 2>&1";
  CHECK(std::system(cmd.c_str()) == 0);
}

TEST_CASE("a checkpoint killed while being written leaves the previous one intact") {
  // Write a valid checkpoint, then let another process rewrite the same file in a loop and kill it
  // at random moments: the file must always read back whole, old or new.
  const std::string scene = silt::test::scene_path("chute");
  const std::string path = "kill_test.ckpt";
  auto sim = silt::test::simulation_from(R"(
[scene]
dimension = 3
[domain]
lo = [0, 0, -0.5]
hi = [40, 20, 30]
periodic = [true, true, false]
[gravity]
magnitude = 1.0
angle = 26.0
[contact]
model = "hooke"
k_n = 2e5
gamma_n = 50.0
friction = 0.5
[[grains]]
radius = 0.49
density = 1.9099
placement = "lattice"
spacing = 1.0
region_lo = [0.0, 0.0, 0.75]
region_hi = [40.0, 20.0, 21.25]
[run]
dt = 1e-4
)");
  (void)scene;
  silt::write_checkpoint(path, sim->model(), sim->state());
  for (int round = 0; round < 6; ++round) {
    const pid_t child = fork();
    if (child == 0) {
      for (;;) silt::write_checkpoint(path, sim->model(), sim->state());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(7 + 13 * round));
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    CHECK_NOTHROW(silt::read_checkpoint(path, sim->model()));
  }
  std::remove(path.c_str());
  std::remove((path + ".tmp").c_str());
}
