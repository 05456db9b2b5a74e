#include "engine/run/stop_signals.hpp"

#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>

namespace ggk::engine {

namespace {

// Everything the handler touches: fixed buffers filled before it is installed.
constexpr std::size_t kPathSize = 4096;
constexpr std::size_t kMessageSize = 3 * kPathSize;
char g_temporary[kPathSize];
char g_lock[kPathSize];
char g_message_published[kMessageSize];
char g_message_unpublished[kMessageSize];
volatile sig_atomic_t g_published = 0;
std::atomic<bool> g_installed{false};
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[3];

void copy(char* target, std::size_t size, const std::string& text) {
  std::strncpy(target, text.c_str(), size - 1);
  target[size - 1] = '\0';
}

extern "C" void on_single_process_stop(int signal) {
  if (g_published == 0) ::unlink(g_temporary);
  ::unlink(g_lock);
  const char* message = g_published != 0 ? g_message_published : g_message_unpublished;
  const char* name = signal == SIGINT    ? "\nggk: interrupted (SIGINT)"
                     : signal == SIGTERM ? "\nggk: stopped by SIGTERM"
                                         : "\nggk: stopped by SIGHUP";
  (void)!::write(STDERR_FILENO, name, std::strlen(name));
  (void)!::write(STDERR_FILENO, message, std::strlen(message));
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  ::sigaction(signal, &default_action, nullptr);
  ::raise(signal);
}

}  // namespace

StopSignals::StopSignals(const std::filesystem::path& job_file, const std::filesystem::path& output,
                         const std::filesystem::path& temporary,
                         const std::filesystem::path& lock_file) {
  if (g_installed.exchange(true)) throw std::logic_error("StopSignals: one instance at a time");
  copy(g_temporary, kPathSize, temporary.string());
  copy(g_lock, kPathSize, lock_file.string());
  const std::string resume =
      "`ggk run " + job_file.string() + " --resume -o " + output.string() + "`\n";
  copy(g_message_published, kMessageSize,
       "; every run written to " + output.string() + " is complete; finish the job with " + resume);
  copy(g_message_unpublished, kMessageSize,
       " before its first run was written; " + output.string() +
           " is as it was; run the job again, or " + resume);
  g_published = temporary.empty() ? 1 : 0;
  struct sigaction action {};
  action.sa_handler = on_single_process_stop;
  sigemptyset(&action.sa_mask);
  for (std::size_t i = 0; i < std::size(kSignals); ++i) {
    ::sigaction(kSignals[i], &action, &g_previous[i]);
  }
}

StopSignals::~StopSignals() {
  for (std::size_t i = 0; i < std::size(kSignals); ++i) {
    ::sigaction(kSignals[i], &g_previous[i], nullptr);
  }
  g_installed = false;
}

void StopSignals::results_published() {
  g_published = 1;
}

}  // namespace ggk::engine
