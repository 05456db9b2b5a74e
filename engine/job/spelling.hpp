#pragma once
// "Did you mean ...?" for misspelt keys and values in job files.

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace ggk::engine {

// Edit distance with insertions, deletions, substitutions and swaps of two
// neighbouring characters, each costing 1 (optimal string alignment distance).
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate `word` most plausibly misspells, or nothing when none is close:
// edit distance (ignoring case) at most max(1, |word| / 3), or `word` a prefix of
// at least 3 characters of a candidate ("max_iter" -> "max_iterations"). Ties go
// to the earlier candidate.
std::optional<std::string_view> closest_spelling(std::string_view word,
                                                 std::span<const std::string_view> candidates);

}  // namespace ggk::engine
