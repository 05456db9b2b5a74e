#pragma once
// The time now in UTC as ggk records it (a results file's "created", a lock's
// "since"): ISO 8601 to the second, "2024-06-01T12:00:00Z". Thread-safe.

#include <ctime>
#include <string>

namespace ggk::engine {

inline std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buffer;
}

}  // namespace ggk::engine
