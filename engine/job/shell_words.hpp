#pragma once
// Commands that ggk prints for the user to paste into a shell (how to resume a
// job, how to finish a partial merge): each word quoted for a POSIX shell (sh,
// bash, zsh) only where it needs it, so that the common case reads as typed.

#include <span>
#include <string>
#include <string_view>

namespace ggk::engine {

// The word unchanged when it holds only characters no POSIX shell treats
// specially (letters, digits, and % + , - . / : = @ _; '=' not first), else in
// single quotes, a single quote inside written as '\''. The empty word is ''.
std::string shell_quoted(std::string_view word);

// The words, each shell_quoted, joined by single spaces.
std::string shell_command(std::span<const std::string> words);

}  // namespace ggk::engine
