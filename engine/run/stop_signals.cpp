#include "engine/run/stop_signals.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <stdexcept>

namespace ggk::engine {

namespace {

// Everything the handler touches: fixed buffers filled before it is installed.
constexpr std::size_t kPathSize = 4096;
constexpr std::size_t kMessageSize = 4 * kPathSize;
char g_temporary[kPathSize];
char g_lock[kPathSize];
char g_message_published[kMessageSize];
char g_message_unpublished[kMessageSize];
char g_message_complete[kMessageSize];
volatile sig_atomic_t g_has_report = 0;
volatile sig_atomic_t g_published = 0;
volatile sig_atomic_t g_complete = 0;
volatile sig_atomic_t g_record_only = 0;
volatile sig_atomic_t g_received = 0;
std::atomic<bool> g_installed{false};
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[3];

void copy(char* target, std::size_t size, const std::string& text) {
  std::strncpy(target, text.c_str(), size - 1);
  target[size - 1] = '\0';
}

void write_text(const char* text) {
  (void)!::write(STDERR_FILENO, text, std::strlen(text));
}

// The one stop path, async-signal-safe: the files, then the message.
void remove_files_and_report(const char* headline, const char* details) {
  if (g_has_report == 0) return;
  if (g_published == 0 && g_complete == 0) ::unlink(g_temporary);
  ::unlink(g_lock);
  write_text("\nggk: ");
  write_text(headline);
  write_text(g_complete != 0    ? g_message_complete
             : g_published != 0 ? g_message_published
                                : g_message_unpublished);
  write_text(details);
}

extern "C" void on_stop_signal(int signal) {
  if (g_record_only != 0) {
    if (g_received == 0) g_received = signal;
    return;
  }
  remove_files_and_report(StopSignals::headline_of(signal), "");
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  ::sigaction(signal, &default_action, nullptr);
  ::raise(signal);
}

}  // namespace

const char* StopSignals::headline_of(int signal) {
  return signal == SIGINT    ? "interrupted (SIGINT)"
         : signal == SIGTERM ? "stopped by SIGTERM"
                             : "stopped by SIGHUP";
}

const char* StopSignals::name_of(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP";
}

StopSignals::StopSignals(Mode mode) {
  if (g_installed.exchange(true)) throw std::logic_error("StopSignals: one instance at a time");
  g_has_report = 0;
  g_published = 0;
  g_complete = 0;
  g_received = 0;
  g_record_only = mode == Mode::kRecord ? 1 : 0;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  for (std::size_t i = 0; i < std::size(kSignals); ++i) {
    // A signal the process inherited as ignored stays ignored (POSIX shells
    // start `cmd &` with SIGINT ignored, nohup with SIGHUP): only a handler that
    // was not SIG_IGN is replaced (the old one holds until the new one is set).
    ::sigaction(kSignals[i], nullptr, &g_previous[i]);
    if (g_previous[i].sa_handler == SIG_IGN) continue;
    ::sigaction(kSignals[i], &action, nullptr);
  }
}

StopSignals::StopSignals(Mode mode, const Report& report) : StopSignals(mode) {
  // Filled while the handler may already run: it reads them only once
  // g_has_report is set, last.
  copy(g_temporary, kPathSize, report.temporary.string());
  copy(g_lock, kPathSize, report.lock_file.string());
  copy(g_message_published, kMessageSize, "; " + report.published + "\n");
  copy(g_message_unpublished, kMessageSize,
       " before its first run was written; " + report.unpublished + "\n");
  copy(g_message_complete, kMessageSize,
       " after the job ended; every run is complete: results in " + report.output.string() + "\n");
  g_published = report.temporary.empty() ? 1 : 0;
  g_has_report = 1;
}

StopSignals::~StopSignals() {
  for (std::size_t i = 0; i < std::size(kSignals); ++i) {
    ::sigaction(kSignals[i], &g_previous[i], nullptr);
  }
  g_has_report = 0;
  g_installed = false;
}

void StopSignals::results_published() {
  g_published = 1;
}

void StopSignals::job_complete() {
  g_complete = 1;
}

int StopSignals::received() const {
  return g_received;
}

void StopSignals::report(const std::string& headline, const std::string& details) const {
  remove_files_and_report(headline.c_str(), details.c_str());
}

}  // namespace ggk::engine
