#include "engine/cli/verify_command.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <ostream>
#include <string>

#include "engine/job/shell_words.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/isolated_reading.hpp"
#include "engine/store/output_lock.hpp"
#include "engine/store/results_verify.hpp"

namespace ggk::engine {

namespace {

// `ggk verify` of a file that `writer` (OutputLock::writer_of) writes now: the
// report goes to a scratch file first (the verifying child prints it there) and
// reaches `out` only when the file is whole; anything else is "being written".
int verify_while_written(const std::string& path, const std::string& writer, std::ostream& out) {
  std::string scratch = (std::filesystem::temp_directory_path() / "ggk-verify-XXXXXX").string();
  const int fd = ::mkstemp(scratch.data());
  if (fd < 0)
    throw UsageError("cannot create a scratch file in " +
                     std::filesystem::temp_directory_path().string());
  ::close(fd);
  int status = 1;
  try {
    status = read_isolated({path}, [&] {
      std::ofstream report(scratch);
      return verify_results(path, report) ? 0 : 1;
    });
  } catch (const ReadingCrash&) {
  } catch (const UsageError&) {
  }
  if (status == 0) {
    std::ifstream report(scratch);
    out << report.rdbuf();
  }
  ::unlink(scratch.c_str());
  if (status == 0) return 0;
  std::cerr << "ggk: " << path << " is being written by " << writer
            << ": it cannot be verified between its writes; run `ggk verify " << shell_quoted(path)
            << "` again when that ggk has finished or stopped\n";
  return 2;
}

}  // namespace

int verify_command(const CommandLine& line) {
  std::ostream discard(nullptr);  // -q: what would be printed, dropped
  std::ostream& out = line.quiet ? discard : std::cout;
  const std::string& path = line.verify_path;
  if (const auto writer = OutputLock::writer_of(path)) {
    return verify_while_written(path, *writer, out);
  }
  try {
    return read_isolated({path}, [&] { return verify_results(path, out) ? 0 : 1; });
  } catch (const ReadingCrash& e) {
    out << path << ": DAMAGED: reading it crashed the HDF5 library (" << e.how()
        << "): an object header is damaged where HDF5 does not check before it "
           "reads; ggk cannot read this file\n";
    return 1;
  }
}

}  // namespace ggk::engine
