#include "engine/job/spelling.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

namespace ggk::engine {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // d[i][j] = distance between a[0, i) and b[0, j), stored row by row.
  const std::size_t width = b.size() + 1;
  std::vector<std::size_t> d((a.size() + 1) * width);
  const auto at = [&d, width](std::size_t i, std::size_t j) -> std::size_t& {
    return d[i * width + j];
  };
  for (std::size_t i = 0; i <= a.size(); ++i) at(i, 0) = i;
  for (std::size_t j = 0; j <= b.size(); ++j) at(0, j) = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = a[i - 1] == b[j - 1] ? 0 : 1;
      at(i, j) = std::min({at(i - 1, j) + 1, at(i, j - 1) + 1, at(i - 1, j - 1) + substitution});
      // Two neighbouring characters swapped ("rusn" for "runs") count as one edit.
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        at(i, j) = std::min(at(i, j), at(i - 2, j - 2) + 1);
      }
    }
  }
  return at(a.size(), b.size());
}

std::optional<std::string_view> closest_spelling(std::string_view word,
                                                 std::span<const std::string_view> candidates) {
  const std::string lowered = lower(word);
  const std::size_t threshold = std::max<std::size_t>(1, word.size() / 3);
  std::optional<std::string_view> best;
  std::size_t best_distance = threshold + 1;
  for (const std::string_view candidate : candidates) {
    const std::string lowered_candidate = lower(candidate);
    const bool truncated = lowered.size() >= 3 && lowered_candidate.starts_with(lowered);
    // The distance is at least the difference in length: skip words that cannot
    // win (and a 1 MB key's table of distances).
    const std::size_t length_gap = lowered.size() > lowered_candidate.size()
                                       ? lowered.size() - lowered_candidate.size()
                                       : lowered_candidate.size() - lowered.size();
    if (length_gap >= best_distance && !truncated) continue;
    std::size_t distance = edit_distance(lowered, lowered_candidate);
    if (distance > threshold && truncated) {
      distance = threshold;  // a truncated key: plausible, but any closer spelling wins
    }
    if (distance < best_distance) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

}  // namespace ggk::engine
