#include "engine/run/existing_output.hpp"

#include <optional>
#include <stdexcept>
#include <string_view>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/isolated_reading.hpp"
#include "engine/run/resume_compatibility.hpp"
#include "engine/store/output_lock.hpp"

namespace ggk::engine {

namespace {

// Why `ggk run --resume` would refuse the file as another job's, read in a
// child; nullopt when it would take it, or the file does not read (damage has
// messages of its own on --resume).
std::optional<std::string> other_job(const Study& study, const std::filesystem::path& output) {
  try {
    read_isolated({output}, [&] {
      const Hdf5File file = Hdf5File::open_read_only(output);
      check_same_job(file, study, output);
      return 0;
    });
  } catch (const UsageError& e) {
    std::string_view why = e.what();
    const std::string prefix = "cannot resume " + output.string() + ": ";
    if (why.starts_with(prefix)) why.remove_prefix(prefix.size());
    if (why.starts_with("it ")) why.remove_prefix(3);  // "it holds the results of ..."
    return std::string(why);
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace

std::string existing_output_refusal(const Study& study, const std::filesystem::path& output,
                                    bool own_output) {
  // A file another ggk writes is not read here (its runs are on their way).
  if (const std::optional<std::string> writer = OutputLock::writer_of(output)) {
    return "output " + output.string() + " exists and is being written by " + *writer +
           ": wait for it to finish, then pass --resume to continue it, or --overwrite to "
           "replace it (deleting its complete runs)";
  }
  const std::optional<std::string> why = other_job(study, output);
  if (!why) {
    return "output " + output.string() +
           " exists: pass --resume to continue it, or --overwrite to replace it (deleting its "
           "complete runs)";
  }
  std::string message = "output " + output.string() + " exists and " + *why;
  if (own_output) {
    message +=
        ". It is the job file's [output] file: a job file copied from another keeps "
        "the original's `name` and `[output] file`; give yours names of their own "
        "(name = \"...\", [output] file = \"results/....h5\")";
  }
  return message;
}

}  // namespace ggk::engine
