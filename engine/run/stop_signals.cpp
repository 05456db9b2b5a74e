#include "engine/run/stop_signals.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <stdexcept>

namespace ggk::engine {

namespace {

// Everything the handler touches: fixed buffers filled before it reads them.
// Two sets: set_report fills the one the handler does not read, then switches
// (g_active), so a signal sees one report whole, the old one or the new.
constexpr std::size_t kPathSize = 4096;
constexpr std::size_t kMessageSize = 4 * kPathSize;
struct ReportBuffers {
  char temporary[kPathSize];
  char lock[kPathSize];
  char message_published[kMessageSize];
  char message_unpublished[kMessageSize];
  char message_complete[kMessageSize];
  volatile sig_atomic_t published;  // the report's own: its temporary was empty
};
ReportBuffers g_reports[2];
volatile sig_atomic_t g_active = 0;
volatile sig_atomic_t g_has_report = 0;
volatile sig_atomic_t g_published = 0;  // results_published() since the last report
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
  const ReportBuffers& report = g_reports[g_active];
  const bool published = g_published != 0 || report.published != 0;
  if (!published && g_complete == 0) ::unlink(report.temporary);
  ::unlink(report.lock);
  write_text("\nggk: ");
  write_text(headline);
  write_text(g_complete != 0 ? report.message_complete
             : published     ? report.message_published
                             : report.message_unpublished);
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
  set_report(report);
}

void StopSignals::set_report(const Report& report) {
  const int next = g_has_report != 0 ? 1 - g_active : g_active;
  ReportBuffers& buffers = g_reports[next];
  copy(buffers.temporary, kPathSize, report.temporary.string());
  copy(buffers.lock, kPathSize, report.lock_file.string());
  copy(buffers.message_published, kMessageSize, "; " + report.published + "\n");
  copy(buffers.message_unpublished, kMessageSize,
       " before its first run was written; " + report.unpublished + "\n");
  copy(buffers.message_complete, kMessageSize,
       " after the job ended; every run is complete: results in " + report.output.string() + "\n");
  buffers.published = report.temporary.empty() ? 1 : 0;
  // The handler reads the buffers only once g_has_report is set, and the set
  // g_active names, which is switched last.
  std::atomic_signal_fence(std::memory_order_seq_cst);
  g_active = next;
  g_published = 0;
  g_has_report = 1;
}

void StopSignals::set_mode(Mode mode) {
  g_record_only = mode == Mode::kRecord ? 1 : 0;
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
