#include "shell/stop_signals.hpp"

#include <csignal>

namespace silt::cli {
namespace {

std::atomic<bool>* g_flag = nullptr;
void (*g_also)() = nullptr;
volatile std::sig_atomic_t g_caught = 0;
struct sigaction g_old_int {
}, g_old_term{}, g_old_hup{};
bool g_hup_installed = false;

extern "C" void on_stop_signal(int sig) {
  g_caught = sig;
  if (g_flag) g_flag->store(true);
  if (g_also) g_also();
}

}  // namespace

bool install_hangup(const struct sigaction& sa, struct sigaction* old) {
  struct sigaction current {};
  sigaction(SIGHUP, nullptr, &current);
  if (old) *old = current;
  if (current.sa_handler == SIG_IGN) return false;
  sigaction(SIGHUP, &sa, nullptr);
  return true;
}

StopSignals::StopSignals(std::atomic<bool>* flag, void (*also)()) {
  g_flag = flag;
  g_also = also;
  g_caught = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sa.sa_flags = SA_RESTART;  // a write to a pipe (stdout) blocked when the signal comes goes on
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
  // SIGHUP (the terminal closed) too, unless it is ignored: `nohup silt run` keeps running.
  g_hup_installed = install_hangup(sa, &g_old_hup);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
  if (g_hup_installed) sigaction(SIGHUP, &g_old_hup, nullptr);
  g_flag = nullptr;
  g_also = nullptr;
}

int StopSignals::caught() { return g_caught; }

const char* StopSignals::describe() {
  switch (g_caught) {
    case SIGTERM: return "terminated (SIGTERM)";
    case SIGHUP: return "hung up (SIGHUP)";
    default: return "interrupted";
  }
}

int StopSignals::exit_code() { return 128 + (g_caught != 0 ? static_cast<int>(g_caught) : SIGINT); }

}  // namespace silt::cli
