#include "session_driver.hpp"

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <regex>
#include <thread>

#include "fuzz_support.hpp"
#include "silt/io.hpp"

namespace silt::fuzz {
namespace {

namespace fs = std::filesystem;
constexpr const char* kFiles = "session_files";  // in the scratch directory
constexpr const char* kWork = "session";
constexpr const char* kScenes[] = {"pack_2d", "bounce_dry", "collision_normal", "paste_iso", "cavity_2d"};

// The scene an input's first byte loads: selector % 4 = 0, 1, 2 the first three (as before the
// paste and the fluid, so that the inputs found then still load what they did); 3 nothing, the
// paste or the fluid as (selector / 4) % 3 = 0, 1, 2.
const char* scene_of(uint8_t selector) {
  if (selector % 4 < 3) return kScenes[selector % 4];
  const int k = selector / 4 % 3;
  return k == 0 ? nullptr : kScenes[2 + k];
}

// Interrupts the line being executed, as Ctrl-C does, once it has taken longer than its budget:
// what bounded_line cannot cut (a run of many grains, a preparation) stays short.
class Watchdog {
 public:
  Watchdog() : thread_([this] { loop(); }) { thread_.detach(); }
  void arm(shell::Session* s) {
    std::lock_guard<std::mutex> lock(mutex_);
    session_ = s;
    deadline_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    cv_.notify_all();
  }
  void disarm() {
    std::lock_guard<std::mutex> lock(mutex_);
    session_ = nullptr;
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (!session_) {
        cv_.wait(lock);
        continue;
      }
      if (cv_.wait_until(lock, deadline_) == std::cv_status::timeout && session_) {
        session_->interrupt();
        deadline_ += std::chrono::milliseconds(50);  // again, for a run the line starts after
      }
    }
  }
  std::mutex mutex_;
  std::condition_variable cv_;
  shell::Session* session_ = nullptr;
  std::chrono::steady_clock::time_point deadline_;
  std::thread thread_;
};

Watchdog* g_watchdog = nullptr;

// A shipped scene made quick: small frames, short runs of its own length (`run` alone) and
// preparation, pack_2d's and paste_iso's 224 disks 60 in a box to match, and the cavity on 16 x 16
// cells (it loads in a millisecond; as long as the file says what these patterns look for, which
// only makes inputs slower otherwise).
std::string small_scene(const std::string& text) {
  static const std::regex length(R"((^|\n)(steps|time) = [^\n]*)"), count(R"(\ncount = 224\n)"),
      box(R"(\nhi = \[19\.5, 19\.5\]\n)"), paste_box(R"(\nhi = \[17\.0, 17\.0\]\n)"),
      cells(R"(\ncells = \[128, 128\]\n)"), size(R"(\nwidth = [0-9]+\nheight = [0-9]+\n)");
  std::string out = std::regex_replace(text, length, "$1steps = " + std::to_string(kFuzzRunSteps));
  out = std::regex_replace(std::regex_replace(out, count, "\ncount = 60\n"), box, "\nhi = [10.0, 10.0]\n");
  out = std::regex_replace(std::regex_replace(out, paste_box, "\nhi = [8.8, 8.8]\n"), cells, "\ncells = [16, 16]\n");
  out = std::regex_replace(out, size, "\n");
  // Keys into the scene's own table (paste_iso's [prepare], cavity_2d's [render]) or one added.
  const auto put = [&out](const std::string& table, const std::string& keys) {
    const std::string header = "\n[" + table + "]\n";
    if (const size_t at = out.find(header); at != std::string::npos) out.insert(at + header.size(), keys);
    else out += header + keys;
  };
  if (out.find("[[grains]]") != std::string::npos)
    put("prepare", "max_steps = " + std::to_string(kFuzzRunSteps) + "\n");
  put("render", "width = 160\nheight = 120\n");
  return out;
}

// The session's directory, a fresh copy of the files. libFuzzer's timer (SIGALRM, for -timeout)
// interrupts system calls, and the copy then fails with EINTR (once in 115,148 inputs): it is
// made again.
void fresh_work_dir() {
  for (int attempt = 0;; ++attempt) {
    std::error_code ec;
    fs::remove_all(kWork, ec);
    if (!ec) fs::copy(kFiles, kWork, ec);
    if (!ec) return;
    if (ec != std::errc::interrupted || attempt == 100) bug("cannot make the session directory: " + ec.message());
  }
}

}  // namespace

void prepare_sessions() {
  set_available_memory(8.0 * (1 << 20));  // some thousands of grains: any scene set larger is refused
  fs::create_directories(kFiles);
  const fs::path files(kFiles);
  for (const char* s : kScenes) {
    const std::string name = std::string(s) + ".toml";
    write_file((files / name).string(), small_scene(read_file(source_path("scenes/" + name))));
    const Model m = compile(load_scene_file((files / name).string()));
    write_checkpoint((files / (std::string(s) + ".ckpt")).string(), m, make_state(m));
  }
  // Scripts to source: a short one, and one that sources itself (the nesting limit).
  write_file((files / "tiny.silt").string(), "print t step\nrun 5\nhash\n");
  write_file((files / "loop.silt").string(), "source loop.silt\n");
  g_watchdog = new Watchdog;
}

SessionDriver::SessionDriver(uint8_t selector) {
  fresh_work_dir();
  if (::chdir(kWork) != 0) bug("cannot enter the session directory");
  session_.emplace(out_, err_, 1);
  if (const char* scene = scene_of(selector)) session_->execute(std::string("load ") + scene + ".toml");
  check_output();
}

SessionDriver::~SessionDriver() {
  session_->execute("quit");
  check_output();
  session_.reset();
  if (::chdir("..") != 0) bug("cannot leave the session directory");
}

std::optional<Clock> SessionDriver::clock() {
  if (!session_->loaded()) return std::nullopt;
  out_.str("");
  session_->execute("print step dt");
  static const std::regex step(R"(step\s*=\s*([0-9]+))"), dt(R"(dt\s*=\s*([-+0-9.eE]+))");
  const std::string out = out_.str();
  std::smatch a, b;
  if (!std::regex_search(out, a, step) || !std::regex_search(out, b, dt)) return std::nullopt;
  const double d = std::stod(b[1].str());
  if (!(d > 0)) return std::nullopt;
  return Clock{std::stoll(a[1].str()), d};
}

bool SessionDriver::line(const std::string& text) {
  if (session_->quit_requested() || lines_ >= kMaxSessionLines) return false;
  ++lines_;
  const std::string bounded = bounded_line(text, [this] { return clock(); });
  g_watchdog->arm(&*session_);
  session_->execute(bounded);
  g_watchdog->disarm();
  check_output();
  return !session_->quit_requested();
}

void SessionDriver::check_output() {
  std::string lines = err_.str();
  for (const std::string& m : session_->take_messages()) lines += m + "\n";
  err_.str("");
  out_.str("");  // not read: it only grows
  std::istringstream in(lines);
  for (std::string l; std::getline(in, l);)
    if (reports_bug(l)) bug("the session reports a bug: " + l);
}

}  // namespace silt::fuzz
