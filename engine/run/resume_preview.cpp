#include "engine/run/resume_preview.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <thread>

#include "engine/job/usage_error.hpp"
#include "engine/run/resume_compatibility.hpp"
#include "engine/store/configuration_groups.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/store/run_extension.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

// The mean of the finite fit_seconds of the file's complete runs.
void read_fit_times(const Hdf5File& file, ResumePreview& preview) {
  const ResultsContents contents = read_contents(file);
  const auto column =
      std::find(contents.metric_names.begin(), contents.metric_names.end(), "fit_seconds");
  if (column == contents.metric_names.end()) return;
  const auto at = static_cast<std::size_t>(column - contents.metric_names.begin());
  double total = 0.0;
  for (const FitRow& fit : contents.fits) {
    if (at >= fit.values.size() || !std::isfinite(fit.values[at])) continue;
    total += fit.values[at];
    ++preview.timed_fits;
  }
  if (preview.timed_fits > 0)
    preview.mean_fit_seconds = total / static_cast<double>(preview.timed_fits);
}

std::string seconds_words(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, seconds < 10.0 ? "%.2g s" : "%.0f s", seconds);
  return text;
}

std::string count_words(std::int64_t count, const std::string& one, const std::string& many) {
  return std::to_string(count) + " " + (count == 1 ? one : many);
}

}  // namespace

ResumePreview preview_resume(const Hdf5File& file, const Study& study, const fs::path& output) {
  ResumePreview preview;
  preview.grows = check_same_job(file, study, output);
  // Where each configuration's runs are now (a grown study renumbers its groups
  // when it resumes; until then they are found by their values).
  std::vector<std::optional<std::string>> locations(study.configurations.size());
  if (study.configurations.front().job.configuration_group.empty()) {
    locations.front() = runs_location(study.job());
  } else {
    for (const ConfigurationGroup& group : configuration_groups(file, study, output)) {
      locations[group.configuration] = study.job().task + "/" + group.name;
    }
  }
  // An adaptive study's shard resumes its own configurations alone.
  const std::optional<ConfigurationsSelected> selected =
      read_results_header(file).configurations_selected;
  for (std::size_t c = 0; c < study.configurations.size(); ++c) {
    if (selected && std::count(selected->configurations.begin(), selected->configurations.end(),
                               static_cast<std::int64_t>(c)) == 0) {
      continue;
    }
    const RunConfiguration& configuration = study.configurations[c];
    const std::vector<SweepPoint> points = expand_points(configuration);
    const std::int32_t runs = configuration.job.runs;
    std::vector<std::int32_t> complete;
    if (locations[c] && file.exists("/" + *locations[c])) {
      complete = complete_runs(file, *locations[c], runs);
    }
    std::vector<std::vector<std::int32_t>> lacking(complete.size());
    for (std::size_t i = 0; i < complete.size(); ++i) {
      try {
        lacking[i] = lacking_points(file, *locations[c], complete[i], points);
      } catch (const std::runtime_error& e) {
        throw UsageError("cannot resume " + output.string() + ": " + e.what());
      }
    }
    if (study.job().adaptive && !lacking.empty()) {
      // An adaptive study's runs hold the points their open cells needed: a run
      // lacks only the job's new values, the points no run of it holds.
      std::vector<std::int32_t> new_values = lacking.front();
      for (const std::vector<std::int32_t>& points_lacking : lacking) {
        std::erase_if(new_values, [&](std::int32_t p) {
          return !std::binary_search(points_lacking.begin(), points_lacking.end(), p);
        });
      }
      for (std::vector<std::int32_t>& points_lacking : lacking) points_lacking = new_values;
    }
    for (const std::vector<std::int32_t>& points_lacking : lacking) {
      if (points_lacking.empty()) {
        ++preview.kept_runs;
      } else {
        ++preview.extended_runs;
        preview.extension_fits += static_cast<std::int64_t>(points_lacking.size());
      }
    }
    const auto missing =
        static_cast<std::int64_t>(runs) - static_cast<std::int64_t>(complete.size());
    preview.new_runs += missing;
    preview.new_run_fits += missing * static_cast<std::int64_t>(points.size());
  }
  read_fit_times(file, preview);
  return preview;
}

std::vector<std::string> preview_words(const ResumePreview& preview, const Study& study,
                                       std::int32_t threads) {
  std::vector<std::string> lines;
  const bool adaptive = study.job().adaptive.has_value();
  if (preview.new_runs == 0 && preview.extended_runs == 0) {
    lines.push_back("ggk run --resume would compute nothing: its " +
                    count_words(preview.kept_runs, "run is", "runs are") +
                    " complete, with every fit of the job");
    return lines;
  }
  std::string what = "ggk run --resume would keep " +
                     count_words(preview.kept_runs, "complete run", "complete runs");
  if (preview.new_runs > 0) {
    what += std::string(", compute ") + (adaptive ? "up to " : "") +
            count_words(preview.new_runs, "run", "runs") + " (" +
            count_words(preview.new_run_fits, "fit", "fits") + ")";
  }
  if (preview.extended_runs > 0) {
    what += std::string(" and grow ") + (adaptive ? "up to " : "") +
            count_words(preview.extended_runs, "complete run", "complete runs") + " by " +
            count_words(preview.extension_fits, "fit", "fits") + " of the job's new values";
  }
  if (preview.grows) what += " (the job grows the file's)";
  if (adaptive) what += "; an adaptive study: its looks decide how many runs it adds";
  lines.push_back(what);
  if (preview.timed_fits == 0) {
    lines.push_back("no time estimate: the file holds no timed fit yet");
    return lines;
  }
  const double fits = static_cast<double>(preview.new_run_fits + preview.extension_fits);
  const double one_thread = fits * preview.mean_fit_seconds;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::int32_t used = threads > 0 ? threads : static_cast<std::int32_t>(cores);
  lines.push_back("at the file's mean fit time (" + seconds_words(preview.mean_fit_seconds) +
                  " over " + count_words(preview.timed_fits, "fit", "fits") + "): about " +
                  seconds_words(one_thread) + " of fitting on one thread, " +
                  seconds_words(one_thread / used) + " at -j " + std::to_string(used) +
                  "; the runs' samples and graphs come on top");
  return lines;
}

}  // namespace ggk::engine
