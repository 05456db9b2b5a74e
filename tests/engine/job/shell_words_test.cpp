#include "engine/job/shell_words.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace ggk::engine {
namespace {

// What a real shell makes of `command`: every word it passes to printf, one per
// line (the words must hold no newline).
std::string words_seen_by(const std::string& shell, const std::string& command) {
  const std::string line = shell + " -c " + shell_quoted("printf '%s\\n' " + command);
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(line.c_str(), "r"), ::pclose);
  if (!pipe) return "<no shell>";
  std::string out;
  std::array<char, 256> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe.get()) != nullptr) {
    out += buffer.data();
  }
  return out;
}

TEST(ShellWords, PlainWordsStayAsTyped) {
  for (const std::string word :
       {"ggk", "run", "jobs/khepera-paper.toml", "runs=5", "-o", "results/x.h5", "--set", "0:3",
        "1e-06", "a,b", "user@host", "50%", "+1", "khepera.motion.turn_deg=30"}) {
    EXPECT_EQ(shell_quoted(word), word);
  }
}

TEST(ShellWords, EverythingElseIsSingleQuoted) {
  EXPECT_EQ(shell_quoted(""), "''");
  EXPECT_EQ(shell_quoted("two words"), "'two words'");
  EXPECT_EQ(shell_quoted("=x"), "'=x'");  // zsh's =cmd expansion
  EXPECT_EQ(shell_quoted("it's"), "'it'\\''s'");
  EXPECT_EQ(shell_quoted("lspi.stopping=\"weights\""), "'lspi.stopping=\"weights\"'");
  EXPECT_EQ(shell_quoted("~/x.h5"), "'~/x.h5'");
}

// The words reach the program as they were, through bash and through sh (dash
// on Debian): what a printed resume command must do when pasted.
TEST(ShellWords, AShellGivesTheProgramTheWordsBack) {
  const std::vector<std::string> words = {"ggk",
                                          "run",
                                          "my jobs/a b.toml",
                                          "--set",
                                          "khepera.sensors.model=\"multiplicative\"",
                                          "--set",
                                          "name='x'",
                                          "--sweep",
                                          "kernels=10,20",
                                          "-o",
                                          "$HOME/out;rm -rf x`y`*.h5",
                                          "",
                                          "tab\there",
                                          "back\\slash",
                                          "!bang",
                                          "=first",
                                          "~tilde",
                                          "#hash",
                                          "a&b|c>d<e",
                                          "(x)"};
  std::string expected;
  for (const std::string& word : words) expected += word + "\n";
  const std::string command = shell_command(words);
  EXPECT_EQ(words_seen_by("bash", command), expected) << command;
  EXPECT_EQ(words_seen_by("sh", command), expected) << command;
}

}  // namespace
}  // namespace ggk::engine
