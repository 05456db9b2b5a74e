#include "engine/store/process_state.hpp"

#include <signal.h>

#include <cerrno>
#include <fstream>
#include <iterator>
#include <sstream>

namespace ggk::engine {

namespace {

// Field `index` (from 3: the state) of /proc/<pid>/stat; empty when unknown.
std::string stat_field(pid_t pid, int index) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  const std::string text{std::istreambuf_iterator<char>(stat), std::istreambuf_iterator<char>()};
  const std::size_t name_end = text.rfind(')');  // the command name may hold spaces and ')'
  if (name_end == std::string::npos) return {};
  std::istringstream fields(text.substr(name_end + 1));
  std::string field;
  for (int at = 3; at <= index && fields >> field; ++at) {
    if (at == index) return field;
  }
  return {};
}

}  // namespace

bool process_alive(pid_t pid) {
  if (pid <= 0) return false;
  if (::kill(pid, 0) != 0 && errno == ESRCH) return false;
  const std::string state = stat_field(pid, 3);
  return state != "Z" && state != "X" && state != "x";
}

std::string process_start(pid_t pid) {
  return stat_field(pid, 22);
}

}  // namespace ggk::engine
