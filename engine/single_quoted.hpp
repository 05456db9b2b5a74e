#pragma once
// 'text', in single quotes, as every message of the engine shows file names,
// object paths and keys. The one piece of text shared by the job room and the
// HDF5 wrapper, so it includes nothing but the standard library. Thread-safe.

#include <string>
#include <string_view>

namespace ggk::engine {

inline std::string single_quoted(std::string_view text) {
  // Appended piece by piece: GCC 12 at -O3 reports a false -Wrestrict on
  // "'" + std::string(...) (GCC bug 105329).
  std::string result;
  result.reserve(text.size() + 2);
  result += '\'';
  result += text;
  result += '\'';
  return result;
}

}  // namespace ggk::engine
