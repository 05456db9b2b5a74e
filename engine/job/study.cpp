#include "engine/job/study.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/resolved_config.hpp"
#include "engine/job/sweep.hpp"

namespace ggk::engine {
namespace {

bool is_builtin_axis(std::string_view key) {
  return std::find(kSweepTableKeys.begin(), kSweepTableKeys.end(), key) != kSweepTableKeys.end();
}

// An axis as written: its keys and, per key, the array of values in the file.
struct WrittenAxis {
  std::vector<std::string> keys;
  std::vector<const toml::array*> values;  // per key, equal lengths
  toml::source_position where;             // for file order
};

// The study axes of [sweep] (dotted keys and [[sweep.zip]] blocks), in file order.
std::vector<WrittenAxis> written_axes(const toml::table& root, const std::string& file) {
  std::vector<WrittenAxis> axes;
  const toml::table* sweep = root.get_as<toml::table>("sweep");
  if (sweep == nullptr) return axes;
  const auto fail_at_sweep = [&](const toml::node& node, const std::string& key,
                                 std::string detail) {
    throw error_at(file, node.source(), "sweep." + key, std::move(detail));
  };
  std::vector<std::string> seen;
  const auto add_key = [&](const std::string& key, const toml::node& node) {
    if (const std::string reason = forbidden_axis_reason(key); !reason.empty()) {
      fail_at_sweep(node, "\"" + key + "\"", reason);
    }
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) {
      fail_at_sweep(node, "\"" + key + "\"", "this key is already an axis of the study");
    }
    seen.push_back(key);
  };
  const auto checked_values = [&](const std::string& key,
                                  const toml::node& node) -> const toml::array* {
    const toml::array* array = node.as_array();
    if (array == nullptr || array->empty()) {
      fail_at_sweep(node, "\"" + key + "\"",
                    "a study axis is a non-empty array of values, got " + describe_value(node) +
                        (node.is_array() ? "" : " (write [" + describe_value(node) + "])"));
    }
    for (const toml::node& element : *array) {
      if (!(element.is_number() || element.is_string() || element.is_boolean())) {
        fail_at_sweep(element, "\"" + key + "\"",
                      "a study axis takes scalar values (numbers, strings, booleans), got " +
                          describe_value(element));
      }
    }
    return array;
  };
  for (const auto& [key, node] : *sweep) {
    const std::string name(key.str());
    if (name == "zip") {
      const toml::array* blocks = node.as_array();
      if (blocks == nullptr || !blocks->is_array_of_tables()) {
        fail_at_sweep(node, "zip",
                      "expected [[sweep.zip]] blocks (tables of keys that vary together), got " +
                          describe_value(node));
      }
      for (const toml::node& block_node : *blocks) {
        const toml::table& block = *block_node.as_table();
        WrittenAxis axis;
        axis.where = block.source().begin;
        for (const auto& [zip_key, zip_node] : block) {
          const std::string zip_name(zip_key.str());
          if (is_builtin_axis(zip_name)) {
            fail_at_sweep(zip_node, "zip." + zip_name,
                          "the built-in axes (basis, kernels, sigma, solver, lambda) combine as "
                          "a product and cannot be zipped; zip other keys");
          }
          add_key(zip_name, zip_node);
          axis.keys.push_back(zip_name);
          axis.values.push_back(checked_values(zip_name, zip_node));
        }
        if (axis.keys.empty()) {
          throw error_at(file, block.source(), "sweep.zip", "an empty [[sweep.zip]] block");
        }
        for (std::size_t k = 1; k < axis.keys.size(); ++k) {
          if (axis.values[k]->size() != axis.values[0]->size()) {
            fail_at_sweep(*block.get(axis.keys[k]), "zip." + axis.keys[k],
                          "the keys of a [[sweep.zip]] block vary together and need as many "
                          "values each: " +
                              std::to_string(axis.values[k]->size()) + " here, " +
                              std::to_string(axis.values[0]->size()) + " for " + axis.keys[0]);
          }
        }
        axes.push_back(std::move(axis));
      }
      continue;
    }
    if (name.find('.') == std::string::npos) {
      // A built-in axis, a top-level key that cannot vary, or a misspelling
      // (which the [sweep] reader reports with a suggestion).
      if (const std::string reason = forbidden_axis_reason(name); !reason.empty()) {
        fail_at_sweep(node, name, reason);
      }
      continue;
    }
    add_key(name, node);
    axes.push_back({{name}, {checked_values(name, node)}, key.source().begin});
  }
  std::stable_sort(axes.begin(), axes.end(), [](const WrittenAxis& a, const WrittenAxis& b) {
    return std::tie(a.where.line, a.where.column) < std::tie(b.where.line, b.where.column);
  });
  return axes;
}

// Sets the dotted `key` of `root` to a copy of `value` (which keeps its place in
// the file, so errors about it point at the axis).
void assign(toml::table& root, const std::string& key, const toml::node& value,
            const std::string& file) {
  toml::table* table = &root;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t dot = key.find('.', begin);
    const std::string part = key.substr(begin, dot == std::string::npos ? dot : dot - begin);
    if (part.empty()) {
      throw error_at(file, value.source(), "sweep.\"" + key + "\"",
                     "not a key of the job (an empty part between dots)");
    }
    if (dot == std::string::npos) {
      value.visit([&](const auto& v) { table->insert_or_assign(part, v); });
      return;
    }
    toml::node* next = table->get(part);
    if (next == nullptr) {
      table->insert(part, toml::table{});
      next = table->get(part);
    }
    if (!next->is_table()) {
      throw error_at(file, value.source(), "sweep.\"" + key + "\"",
                     "not a key of the job: " + key.substr(0, dot) + " is not a table");
    }
    table = next->as_table();
    begin = dot + 1;
  }
}

// Indices of every combination of the axes' values, the last axis fastest.
std::vector<std::vector<std::size_t>> combinations(const std::vector<std::size_t>& sizes) {
  std::vector<std::vector<std::size_t>> all(1);
  for (const std::size_t size : sizes) {
    std::vector<std::vector<std::size_t>> next;
    next.reserve(all.size() * size);
    for (const auto& prefix : all) {
      for (std::size_t i = 0; i < size; ++i) {
        next.push_back(prefix);
        next.back().push_back(i);
      }
    }
    all = std::move(next);
  }
  return all;
}

void remove_study_axes(toml::table& root, const std::vector<WrittenAxis>& written) {
  if (toml::table* sweep = root.get_as<toml::table>("sweep")) {
    for (const WrittenAxis& axis : written) {
      for (const std::string& key : axis.keys) sweep->erase(key);
    }
    sweep->erase("zip");
  }
}

struct Expansion {
  const std::vector<WrittenAxis>& written;
  std::vector<StudyAxis>& axes;
  const std::filesystem::path& source_file;
  std::span<const TaskTable> tasks;
  const JobLoadOptions& options;
  const std::string& source_text;
  const std::string& toml_text;

  // The job at one point: the job with the listed axes at the listed values.
  JobSpec parse_point(const std::vector<std::size_t>& axis_ids,
                      const std::vector<std::size_t>& value_ids,
                      std::vector<AxisAssignment>& assignments) const {
    const std::string file = source_file.string();
    // The job's TOML read afresh (a copied toml++ table forgets where its values
    // were, and errors would lose their line), less the study axes, plus the
    // point's values.
    toml::table root = parse_job_toml(toml_text, file, options);
    remove_study_axes(root, written);
    std::string description;
    for (std::size_t a = 0; a < axis_ids.size(); ++a) {
      const WrittenAxis& axis = written[axis_ids[a]];
      for (std::size_t k = 0; k < axis.keys.size(); ++k) {
        const toml::node& value = *axis.values[k]->get(value_ids[a]);
        assign(root, axis.keys[k], value, file);
        description +=
            (description.empty() ? "" : ", ") + axis.keys[k] + " = " + describe_value(value);
      }
    }
    JobSpec job;
    try {
      job = parse_job_table(root, source_text, source_file, tasks, options);
    } catch (const JobError& e) {
      // A value copied into the job has lost its place in the file: the error
      // about it points at the axis value in [sweep].
      JobFileLocation where{e.line(), e.column()};
      for (std::size_t a = 0; a < axis_ids.size() && where.line == 0; ++a) {
        const WrittenAxis& axis = written[axis_ids[a]];
        for (std::size_t k = 0; k < axis.keys.size(); ++k) {
          if (axis.keys[k] == e.key_path() && e.file() == file) {
            where = location_of(axis.values[k]->get(value_ids[a])->source());
          }
        }
      }
      if (description.empty()) throw;  // the configuration of fit-level axes only
      throw JobError(e.file(), where, e.key_path(),
                     e.detail() + " (at the study point " + description + ")");
    }
    for (std::size_t a = 0; a < axis_ids.size(); ++a) {
      const WrittenAxis& axis = written[axis_ids[a]];
      StudyAxis& study_axis = axes[axis_ids[a]];
      for (std::size_t k = 0; k < axis.keys.size(); ++k) {
        const std::optional<std::string> value = job.resolved.value(axis.keys[k]);
        if (!value) {
          throw error_at(file, axis.values[k]->get(value_ids[a])->source(),
                         "sweep.\"" + axis.keys[k] + "\"", "not a key this job reads");
        }
        study_axis.values[value_ids[a]][k] = *value;
        assignments.push_back({axis.keys[k], *value});
      }
    }
    return job;
  }
};

// Two points of one axis set that resolve alike: the study would compute one
// configuration twice.
template <class Items>
void reject_repeats(const Items& items, const std::string& file, const std::string& what) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      bool same = items[i].assignments.size() == items[j].assignments.size();
      for (std::size_t k = 0; same && k < items[i].assignments.size(); ++k) {
        same = items[i].assignments[k].value == items[j].assignments[k].value;
      }
      if (!same) continue;
      std::string values;
      for (const AxisAssignment& a : items[i].assignments) {
        values += (values.empty() ? "" : ", ") + a.key + " = " + a.value;
      }
      throw JobError(file, {}, "sweep",
                     what + " " + values +
                         " appears twice (values of an axis must be distinct "
                         "as numbers: 30 and 30.0 are one value)");
    }
  }
}

// The values of the axis `name` of the study as text (a built-in axis's from the
// job's [sweep], a study axis's canonical values unquoted), or nullopt when no
// axis has that name.
std::optional<std::vector<std::string>> axis_value_texts(const Study& study,
                                                         const std::string& name) {
  const SweepAxes& sweep = study.job().sweep;
  std::vector<std::string> texts;
  if (name == "basis") {
    for (const KernelType type : sweep.basis) texts.emplace_back(kernel_type_name(type));
  } else if (name == "kernels") {
    for (const std::int32_t count : sweep.kernels) texts.push_back(canonical_integer(count));
  } else if (name == "sigma") {
    for (const double sigma : sweep.sigma) texts.push_back(canonical_number(sigma));
  } else if (name == "solver") {
    for (const auto solver : sweep.solver) texts.emplace_back(solver_name(solver));
  } else if (name == "lambda") {
    for (const double lambda : sweep.lambda) texts.push_back(canonical_number(lambda));
  } else {
    for (const StudyAxis& axis : study.axes) {
      for (std::size_t k = 0; k < axis.keys.size(); ++k) {
        if (axis.keys[k] != name) continue;
        for (const auto& value : axis.values) texts.push_back(unquoted(value[k]));
        return texts;
      }
    }
    return std::nullopt;
  }
  return texts;
}

// An adaptive rule's comparisons name axes the study sweeps, and two of each
// one's values (adaptive_rule.hpp).
void check_adaptive_rule(const Study& study, const std::string& file) {
  const std::optional<AdaptiveRule>& rule = study.job().adaptive;
  if (!rule) return;
  for (const AdaptiveComparison& comparison : rule->comparisons) {
    const auto values = axis_value_texts(study, comparison.axis);
    const std::string what = "compare = \"" + shortened(comparison.text()) + "\": ";
    if (!values) {
      std::string axes = "basis, kernels, sigma, solver, lambda";
      for (const StudyAxis& axis : study.axes) {
        for (const std::string& key : axis.keys) axes += ", " + key;
      }
      throw JobError(file, {}, "adaptive.compare",
                     what + "the study has no axis '" + shortened(comparison.axis) +
                         "' (its axes: " + axes + ")");
    }
    for (const std::string* side : {&comparison.a, &comparison.b}) {
      const bool known = std::any_of(values->begin(), values->end(), [&](const std::string& v) {
        return same_value_text(v, *side);
      });
      if (!known) {
        std::string listed;
        for (const std::string& v : *values) listed += (listed.empty() ? "" : ", ") + v;
        throw JobError(file, {}, "adaptive.compare",
                       what + comparison.axis + " has no value '" + shortened(*side) +
                           "' in [sweep] (its values: " + listed + ")");
      }
    }
  }
}

}  // namespace

std::string forbidden_axis_reason(const std::string& key) {
  if (key == "name" || key == "task") {
    return "'" + key + "' names the job: a study is one job, so it cannot vary";
  }
  if (key == "runs") {
    return "'runs' is the number of runs of every configuration: set it with runs = N";
  }
  if (key == "seed") {
    return "'seed' cannot vary: every configuration draws run r from the same streams "
           "(common random numbers), which is what pairs them; study seeds with more runs";
  }
  if (key.rfind("output.", 0) == 0 || key == "output") {
    return "where results go is not an axis: a study is one results file";
  }
  if (key.rfind("adaptive.", 0) == 0 || key == "adaptive") {
    return "the adaptive rule is one for the whole study: it cannot vary";
  }
  if (key.rfind("sweep.", 0) == 0) {
    return "write the built-in axes as [sweep] keys (kernels = [...]), not as dotted keys";
  }
  return "";
}

StageLevel stage_of(const std::string& key) {
  if (is_builtin_axis(key)) return StageLevel::kFit;
  if (key.rfind("lspi.", 0) == 0 && key != "lspi.fold_duplicates") return StageLevel::kFit;
  return StageLevel::kRun;
}

Study parse_study(std::string toml_text, const std::filesystem::path& source_file,
                  std::span<const TaskTable> tasks, const JobLoadOptions& options) {
  const std::string file = source_file.string();
  const toml::table root = parse_job_toml(toml_text, file, options);
  const std::string source_text = job_source_text(toml_text, root, file, options);
  const std::vector<WrittenAxis> written = written_axes(root, file);

  Study study;
  if (written.empty()) {  // a plain job: its one configuration, from the TOML read above
    RunConfiguration configuration;
    configuration.job = parse_job_table(root, source_text, source_file, tasks, options);
    configuration.variants.push_back({{}, configuration.job.lspi});
    study.configurations.push_back(std::move(configuration));
    check_adaptive_rule(study, file);
    return study;
  }
  std::vector<std::size_t> run_axes, fit_axes, run_sizes, fit_sizes;
  for (std::size_t a = 0; a < written.size(); ++a) {
    StudyAxis axis;
    axis.keys = written[a].keys;
    axis.values.assign(written[a].values[0]->size(),
                       std::vector<std::string>(written[a].keys.size()));
    axis.level = std::all_of(axis.keys.begin(), axis.keys.end(),
                             [](const std::string& k) { return stage_of(k) == StageLevel::kFit; })
                     ? StageLevel::kFit
                     : StageLevel::kRun;
    (axis.level == StageLevel::kRun ? run_axes : fit_axes).push_back(a);
    (axis.level == StageLevel::kRun ? run_sizes : fit_sizes).push_back(axis.values.size());
    study.axes.push_back(std::move(axis));
  }

  const Expansion expansion{written, study.axes,  source_file, tasks,
                            options, source_text, toml_text};
  const auto run_points = combinations(run_sizes);
  const auto fit_points = combinations(fit_sizes);
  for (const auto& run_point : run_points) {
    RunConfiguration configuration;
    configuration.index = static_cast<std::int32_t>(study.configurations.size());
    configuration.job = expansion.parse_point(run_axes, run_point, configuration.assignments);
    if (!run_axes.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "config_%03d", configuration.index);
      configuration.job.configuration_group = name;
    }
    if (fit_axes.empty()) {
      configuration.variants.push_back({{}, configuration.job.lspi});
    } else {
      // The run-level values first, then the fit-level ones over them.
      std::vector<std::size_t> axis_ids = run_axes;
      axis_ids.insert(axis_ids.end(), fit_axes.begin(), fit_axes.end());
      for (const auto& fit_point : fit_points) {
        std::vector<std::size_t> value_ids = run_point;
        value_ids.insert(value_ids.end(), fit_point.begin(), fit_point.end());
        std::vector<AxisAssignment> assignments;
        const JobSpec job = expansion.parse_point(axis_ids, value_ids, assignments);
        assignments.erase(
            assignments.begin(),
            assignments.begin() + static_cast<std::ptrdiff_t>(configuration.assignments.size()));
        configuration.variants.push_back({std::move(assignments), job.lspi});
      }
      reject_repeats(configuration.variants, file, "the fit-level point");
    }
    study.configurations.push_back(std::move(configuration));
  }
  reject_repeats(study.configurations, file, "the run configuration");
  check_adaptive_rule(study, file);
  return study;
}

ResolvedConfig resolved_of(const Study& study) {
  ResolvedConfig resolved = study.job().resolved;
  if (!study.has_axes()) return resolved;
  std::string axes;
  for (const StudyAxis& axis : study.axes) {
    std::string keys;
    for (std::size_t k = 0; k < axis.keys.size(); ++k) {
      keys += (k == 0 ? "" : "+") + axis.keys[k];
      std::string values;
      for (const auto& value : axis.values) values += (values.empty() ? "" : ", ") + value[k];
      resolved.replace(axis.keys[k], "[" + values + "]", true);
    }
    axes += (axes.empty() ? "" : ", ") + canonical_string(keys);
  }
  resolved.replace("study.axes", "[" + axes + "]", true);
  return resolved;
}

std::string resolved_job_toml(const Study& study) {
  const ResolvedConfig resolved = resolved_of(study);
  std::set<std::string> axis_keys = {"study.axes"};
  for (const StudyAxis& axis : study.axes) axis_keys.insert(axis.keys.begin(), axis.keys.end());
  // Each key under its table ("khepera.motion.turn_deg": [khepera.motion] turn_deg);
  // the root's keys (name, task, runs, seed) first, as TOML requires.
  std::map<std::string, std::string> tables;
  for (const std::string& key : resolved.keys()) {
    if (axis_keys.count(key) > 0) continue;
    const std::size_t dot = key.rfind('.');
    const std::string table = dot == std::string::npos ? "" : key.substr(0, dot);
    const std::string name = dot == std::string::npos ? key : key.substr(dot + 1);
    const std::string line = name + " = " + *resolved.value(key);
    // Unused in any configuration: giving it would be refused at that point.
    std::optional<std::string> unused;
    for (const RunConfiguration& configuration : study.configurations) {
      if (!unused) unused = configuration.job.resolved.unused_reason(key);
    }
    tables[table] += unused ? "# " + line + "  (unused: " + *unused + ")\n" : line + "\n";
  }
  std::string zips;
  for (const StudyAxis& axis : study.axes) {
    std::string lines;
    for (std::size_t k = 0; k < axis.keys.size(); ++k) {
      std::string values;
      for (const auto& value : axis.values) values += (values.empty() ? "" : ", ") + value[k];
      lines += canonical_string(axis.keys[k]) + " = [" + values + "]\n";
    }
    if (axis.keys.size() == 1) {
      tables["sweep"] += lines;
    } else {
      zips += "\n[[sweep.zip]]\n" + lines;
    }
  }
  std::string text =
      "# The resolved job (ggk validate --print): every key ggk reads, with the value it\n"
      "# uses, defaults filled in.\n";
  text += tables[""];
  for (const auto& [table, lines] : tables) {
    if (table.empty()) continue;
    text += "\n[" + table + "]\n" + lines;
    if (table == "sweep") text += zips;
  }
  if (tables.count("sweep") == 0 && !zips.empty()) text += "\n[sweep]" + zips;
  return text;
}

std::string study_values_text(const std::vector<AxisAssignment>& assignments) {
  std::string text;
  for (const AxisAssignment& assignment : assignments) {
    text += assignment.key + " = " + assignment.value + "\n";
  }
  return text;
}

std::string unit_words(const Study& study, WorkUnit unit) {
  const std::string run = "run " + std::to_string(unit.run);
  if (unit.configuration < 0 ||
      static_cast<std::size_t>(unit.configuration) >= study.configurations.size()) {
    return run + " of configuration " + std::to_string(unit.configuration);
  }
  const std::string& group = study.configurations[unit.configuration].job.configuration_group;
  return group.empty() ? run : run + " of " + group;
}

Study study_of(JobSpec job) {
  Study study;
  RunConfiguration configuration;
  configuration.variants.push_back({{}, job.lspi});
  configuration.job = std::move(job);
  study.configurations.push_back(std::move(configuration));
  return study;
}

Study load_study(const std::filesystem::path& path, std::span<const TaskTable> tasks,
                 const JobLoadOptions& options) {
  return parse_study(read_job_file(path), path, tasks, options);
}

std::string unquoted(const std::string& value) {
  if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
    return value.substr(1, value.size() - 2);
  }
  return value;
}

std::string variant_label(const FitVariant& variant) {
  std::string label;
  for (const AxisAssignment& assignment : variant.assignments) {
    label += (label.empty() ? "" : ",") + assignment.key + "=" + unquoted(assignment.value);
  }
  return label;
}

std::vector<SweepPoint> expand_points(const RunConfiguration& configuration) {
  std::vector<SweepPoint> points;
  for (const SweepPoint& base : expand_sweep(configuration.job)) {
    for (std::size_t v = 0; v < configuration.variants.size(); ++v) {
      SweepPoint point = base;
      point.index = static_cast<std::int32_t>(points.size());
      point.variant = static_cast<std::int32_t>(v);
      point.lspi = configuration.variants[v].lspi;
      point.variant_label = variant_label(configuration.variants[v]);
      point.study_values = configuration.assignments;
      point.study_values.insert(point.study_values.end(),
                                configuration.variants[v].assignments.begin(),
                                configuration.variants[v].assignments.end());
      points.push_back(point);
    }
  }
  return points;
}

}  // namespace ggk::engine
