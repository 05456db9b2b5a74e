#pragma once
// A text from a file (an HDF5 error, an attribute) shown on one line of a
// message: line breaks become spaces; a text longer than `limit` is cut and
// says how long it was (a file may hold any text: an 8 MB attribute is not
// printed whole). Used by ggk verify and ggk info.

#include <cstddef>
#include <string>

namespace ggk::engine {

inline std::string one_line(std::string text, std::size_t limit = 300) {
  const std::size_t bytes = text.size();
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  if (bytes <= limit) return text;
  return text.substr(0, limit) + "... (" + std::to_string(bytes) + " bytes)";
}

}  // namespace ggk::engine
