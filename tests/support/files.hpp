#pragma once
// Scratch folders and whole-file reads for tests.

#include <filesystem>
#include <string>
#include <string_view>

namespace ggk::test_support {

// A fresh folder under the system's temporary directory ("<prefix>-XXXXXX"),
// removed with everything in it when the object goes. Throws std::runtime_error
// when it cannot be made.
class ScratchDir {
 public:
  explicit ScratchDir(std::string_view prefix);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// The bytes of `path`; empty when it cannot be read.
std::string file_bytes(const std::filesystem::path& path);

// Writes `text` to `path` (binary, truncating) and returns `path`.
std::filesystem::path write_file(const std::filesystem::path& path, std::string_view text);

}  // namespace ggk::test_support
