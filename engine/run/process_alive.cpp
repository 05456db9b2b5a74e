#include "engine/run/process_alive.hpp"

#include <fstream>
#include <string>

namespace ggk::engine {

bool process_alive(pid_t pid) {
  if (pid <= 0) return false;
  // /proc/<pid>/stat: "pid (comm) state ..."; comm may hold spaces and ')', so the
  // state is the first field after the last ')'.
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!stat || !std::getline(stat, line)) return false;
  const std::string::size_type close = line.rfind(')');
  if (close == std::string::npos || close + 2 >= line.size()) return false;
  const char state = line[close + 2];
  return state != 'Z' && state != 'X' && state != 'x';
}

}  // namespace ggk::engine
