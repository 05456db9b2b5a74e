#include "engine/job/job_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "engine/job/job_input.hpp"
#include "engine/job/study.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/toml_table_reader.hpp"
#include "engine/single_quoted.hpp"

namespace ggk::engine {
namespace {

constexpr std::int64_t kInt32Max = std::numeric_limits<std::int32_t>::max();
// A job's name names its default output file; 100 characters keep
// "<name>.h5" and the names derived from it far below NAME_MAX (255 bytes).
constexpr std::size_t kMaxNameCharacters = 100;
// [lspi] max_iterations: policy iteration settles in a few to tens of evaluations
// (the paper's jobs cap it at 20; a fit still changing then is cycling between
// near-equal policies, not converging). 1000 leaves room for studies of the
// stopping rules; beyond it a job is one that never ends.
constexpr IntegerRange kMaxIterationsRange{1, 1000};
// The longest file name (one path component) Linux file systems take, NAME_MAX.
constexpr std::size_t kMaxFileNameBytes = 255;

// The keys every job has; the registered tasks' names (their tables) join them.
constexpr std::array<std::string_view, 10> kCommonTopLevelKeys = {
    "name", "task", "runs", "seed", "sweep", "basis", "pvf", "lspi", "output", "adaptive"};
constexpr std::array<std::string_view, 2> kBasisKeys = {"scheme", "truncation"};
constexpr std::array<std::string_view, 3> kPvfKeys = {"laplacian", "edge_weights", "actions"};
constexpr std::array<std::string_view, 9> kLspiKeys = {
    "gamma",    "max_iterations",   "fold_duplicates",     "min_rcond",
    "stopping", "weight_tolerance", "evaluate_iterations", "linear_algebra",
    "ridge"};
constexpr std::array<std::string_view, 3> kOutputKeys = {"file", "compression", "store_matrices"};

constexpr std::array<std::string_view, 3> kKernelTypeNames = {"ggk", "ogk", "pvf"};
constexpr std::array<std::string_view, 2> kLaplacianNames = {"normalized", "combinatorial"};
constexpr std::array<std::string_view, 3> kEdgeWeightNames = {"unit", "gaussian", "distance"};
constexpr std::array<std::string_view, 2> kSolverNames = {"brm", "lstdq"};
constexpr std::array<std::string_view, 2> kSchemeNames = {"shift", "copy"};
constexpr std::array<std::string_view, 2> kStoppingNames = {"policy", "weights"};
constexpr std::array<std::string_view, 3> kLinearAlgebraNames = {"auto", "sparse", "dense"};
constexpr std::array<std::string_view, 2> kRidgeScaleNames = {"absolute", "relative"};

bool is_valid_name(std::string_view name) {
  if (name.empty()) return false;
  for (const char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

KernelType kernel_type_from(const std::string& name) {
  return name == "ggk" ? KernelType::ggk : name == "ogk" ? KernelType::ogk : KernelType::pvf;
}
kernels::LspiSolver solver_from(const std::string& name) {
  return name == "brm" ? kernels::LspiSolver::brm : kernels::LspiSolver::lstdq;
}
kernels::BasisScheme scheme_from(const std::string& name) {
  return name == "shift" ? kernels::BasisScheme::shift : kernels::BasisScheme::copy;
}

SweepAxes parse_sweep(const TomlTableReader& job) {
  const std::optional<TomlTableReader> sweep = job.subtable("sweep", kSweepTableKeys);
  if (!sweep) job.fail("sweep", "required table [sweep] is missing");
  SweepAxes axes;
  for (const std::string& name :
       sweep->choice_set("basis", kKernelTypeNames, std::vector<std::string>{"ggk", "ogk"})) {
    axes.basis.push_back(kernel_type_from(name));
  }
  for (const std::int64_t count : sweep->integer_set("kernels", {1, kInt32Max})) {
    axes.kernels.push_back(static_cast<std::int32_t>(count));
  }
  axes.sigma = sweep->number_set("sigma", NumberRange::above(0.0));
  for (const std::string& name :
       sweep->choice_set("solver", kSolverNames, std::vector<std::string>{"brm"})) {
    axes.solver.push_back(solver_from(name));
  }
  axes.lambda = sweep->number_set("lambda", NumberRange::at_least(0.0), std::vector<double>{1e-6});
  return axes;
}

BasisSettings parse_basis(const TomlTableReader& job) {
  const TomlTableReader table = job.subtable_or_empty("basis", kBasisKeys);
  BasisSettings basis;
  basis.scheme = scheme_from(
      table.choice("scheme", kSchemeNames, std::string(basis_scheme_name(basis.scheme))));
  basis.truncation = table.number("truncation", NumberRange::half_open(0.0, 1.0), basis.truncation);
  return basis;
}

// [pvf]: the defaults are documented in jobs/README.md.
PvfSettings parse_pvf(const TomlTableReader& job) {
  const TomlTableReader table = job.subtable_or_empty("pvf", kPvfKeys);
  PvfSettings pvf;
  pvf.laplacian =
      table.choice("laplacian", kLaplacianNames,
                   std::string(kernels::laplacian_kind_name(pvf.laplacian))) == "normalized"
          ? kernels::LaplacianKind::normalized
          : kernels::LaplacianKind::combinatorial;
  const std::string weights = table.choice(
      "edge_weights", kEdgeWeightNames, std::string(kernels::edge_affinity_name(pvf.edge_weights)));
  pvf.edge_weights = weights == "unit"       ? kernels::EdgeAffinity::unit
                     : weights == "gaussian" ? kernels::EdgeAffinity::gaussian
                                             : kernels::EdgeAffinity::distance;
  pvf.actions = scheme_from(
      table.choice("actions", kSchemeNames, std::string(basis_scheme_name(pvf.actions))));
  return pvf;
}

LspiSettings parse_lspi(const TomlTableReader& job) {
  const TomlTableReader table = job.subtable_or_empty("lspi", kLspiKeys);
  LspiSettings lspi;
  lspi.gamma = table.number("gamma", NumberRange::half_open(0.0, 1.0), lspi.gamma);
  lspi.max_iterations = static_cast<std::int32_t>(
      table.integer("max_iterations", kMaxIterationsRange, lspi.max_iterations));
  lspi.fold_duplicates = table.boolean("fold_duplicates", lspi.fold_duplicates);
  lspi.min_rcond = table.number("min_rcond", NumberRange::open(0.0, 1.0), lspi.min_rcond);
  lspi.stopping = table.choice("stopping", kStoppingNames, "policy") == "weights"
                      ? kernels::LspiStopping::weights_converged
                      : kernels::LspiStopping::policy_unchanged;
  lspi.weight_tolerance =
      table.number("weight_tolerance", NumberRange::at_least(0.0), lspi.weight_tolerance);
  lspi.evaluate_iterations = table.boolean("evaluate_iterations", lspi.evaluate_iterations);
  const std::string linear_algebra = table.choice("linear_algebra", kLinearAlgebraNames, "auto");
  lspi.linear_algebra = linear_algebra == "sparse"  ? kernels::LinearAlgebra::sparse
                        : linear_algebra == "dense" ? kernels::LinearAlgebra::dense
                                                    : kernels::LinearAlgebra::automatic;
  lspi.ridge = table.choice("ridge", kRidgeScaleNames, "absolute") == "relative"
                   ? kernels::RidgeScale::relative
                   : kernels::RidgeScale::absolute;
  return lspi;
}

// Why `file` cannot be the output file, or nothing. Checks its directory with
// access(2) and creates nothing.
std::optional<std::string> output_file_problem(const std::filesystem::path& file) {
  if (file.empty()) return "the output file name is empty";
  const std::string shown = single_quoted(shortened(file.string()));
  if (!file.has_filename()) return shown + " names a directory, not a file";
  for (const std::filesystem::path& part : file) {
    if (part.native().size() > kMaxFileNameBytes) {
      return shown + ": the name " + single_quoted(shortened(part.native())) + " is " +
             std::to_string(part.native().size()) + " bytes, more than file systems allow (" +
             std::to_string(kMaxFileNameBytes) + ")";
    }
  }
  const std::filesystem::path directory = file.has_parent_path() ? file.parent_path() : ".";
  const std::string shown_directory = single_quoted(shortened(directory.string()));
  std::error_code error;
  const auto directory_status = std::filesystem::status(directory, error);
  if (!std::filesystem::exists(directory_status)) {
    std::string where;
    if (directory.is_relative()) {
      std::error_code cwd_error;
      where = " (an output file is relative to the working directory, " +
              single_quoted(shortened(std::filesystem::current_path(cwd_error).string())) +
              ", not to the job file: run from the folder that holds it, or pass -o)";
    }
    return "directory " + shown_directory + " of " + shown + " does not exist" + where;
  }
  if (!std::filesystem::is_directory(directory_status)) {
    return shown_directory + " in " + shown + " is not a directory";
  }
  if (::access(directory.c_str(), W_OK | X_OK) != 0) {
    return "directory " + shown_directory + " of " + shown + " is not writable (" +
           std::strerror(errno) + ")";
  }
  const auto file_status = std::filesystem::status(file, error);
  if (std::filesystem::is_directory(file_status)) return shown + " is a directory";
  if (std::filesystem::exists(file_status) && ::access(file.c_str(), W_OK) != 0) {
    return shown + " exists and is not writable (" + std::strerror(errno) + ")";
  }
  return results_extension_problem(file);
}

OutputSettings parse_output(const TomlTableReader& job, const std::string& job_name,
                            const JobLoadOptions& options) {
  const TomlTableReader table = job.subtable_or_empty("output", kOutputKeys);
  OutputSettings output;
  output.file = table.string("file", "results/" + job_name + ".h5");
  output.compression = static_cast<std::int32_t>(table.integer("compression", {0, 9}, 4));
  output.store_matrices = table.boolean("store_matrices", output.store_matrices);
  if (options.output_file) {
    output.file = *options.output_file;
    if (options.check_output) {
      if (const auto problem = output_file_problem(output.file)) {
        throw JobError(table.file(), {}, "", "output file given on the command line: " + *problem);
      }
    }
  } else if (options.check_output) {
    if (const auto problem = output_file_problem(output.file)) {
      table.fail("file", *problem + (table.has("file") ? "" : " (the default output file)"));
    }
  }
  return output;
}

// The top-level keys of a job for these tasks: the common ones, then each task's
// table. A task named like a common key, twice, or without a parser is a
// programmer error in the task list.
std::vector<std::string_view> top_level_keys(std::span<const TaskTable> tasks) {
  std::vector<std::string_view> keys(kCommonTopLevelKeys.begin(), kCommonTopLevelKeys.end());
  for (const TaskTable& task : tasks) {
    if (task.name.empty() || task.parse == nullptr ||
        std::find(keys.begin(), keys.end(), task.name) != keys.end()) {
      throw std::logic_error("task list: task '" + std::string(task.name) +
                             "' is unnamed, has no table parser, or its name is taken");
    }
    keys.push_back(task.name);
  }
  return keys;
}

// Copies every key of `from` into `into`: a table into a table merges, anything
// else replaces. Keys and values keep their source (the --set option).
void merge_table(toml::table& into, const toml::table& from) {
  for (const auto& entry : from) {
    // Not a structured binding: clang 14 cannot capture one in the lambda below.
    const toml::key& key = entry.first;
    const toml::node& node = entry.second;
    toml::node* existing = into.get(key.str());
    if (node.is_table() && existing != nullptr && existing->is_table()) {
      merge_table(*existing->as_table(), *node.as_table());
      continue;
    }
    into.erase(key.str());
    node.visit([&](const auto& value) { into.insert(key, value); });
  }
}

std::string toml_literal(std::string_view text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

void apply_override(toml::table& root, const std::string& text) {
  const std::string source = "--set " + shortened(text);
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw JobError(source, {}, "",
                   "expected KEY=VALUE, e.g. --set runs=5 or --set khepera.motion.turn_deg=30");
  }
  const std::string key = text.substr(0, equals);
  const std::string value = text.substr(equals + 1);
  toml::table snippet;
  try {
    snippet = toml::parse(key + " = " + value, std::string_view(source));
  } catch (const toml::parse_error&) {
    // Not a TOML value: a bare word is a string (--set name=quick2).
    try {
      snippet = toml::parse(key + " = " + toml_literal(value), std::string_view(source));
    } catch (const toml::parse_error& error) {
      throw JobError(source, {}, "",
                     "expected KEY=VALUE with KEY a dotted key of the job file: " +
                         std::string(error.description()));
    }
  }
  merge_table(root, snippet);
}

// A TOML value in ResolvedConfig's canonical form: tables inline with sorted
// keys, arrays inline.
std::string canonical_node(const toml::node& node) {
  if (const auto* value = node.as_integer()) return canonical_integer(value->get());
  if (const auto* value = node.as_floating_point()) return canonical_number(value->get());
  if (const auto* value = node.as_string()) return canonical_string(value->get());
  if (const auto* value = node.as_boolean()) return canonical_boolean(value->get());
  if (const auto* array = node.as_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < array->size(); ++i) {
      text += (i > 0 ? ", " : "") + canonical_node(*array->get(i));
    }
    return text + "]";
  }
  if (const auto* table = node.as_table()) {
    std::string text = "{";
    bool first = true;
    for (const auto& [key, value] : *table) {  // toml++ keeps keys sorted
      text += (first ? " " : ", ") + canonical_string(key.str()) + " = " + canonical_node(value);
      first = false;
    }
    return text + (first ? "}" : " }");
  }
  std::ostringstream text;  // dates and times: TOML's own form
  node.visit([&text](const auto& value) { text << value; });
  return text.str();
}

// Records the keys of `table` that no getter read (arrays of tables, say), as
// they are written: the resolved configuration then holds every key of the job.
void record_unread_keys(const toml::table& table, const std::string& prefix,
                        ResolvedConfig& resolved) {
  for (const auto& [key, value] : table) {
    const std::string path =
        prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
    if (const auto* subtable = value.as_table()) {
      record_unread_keys(*subtable, path, resolved);
    } else if (!resolved.contains(path)) {
      resolved.record(path, canonical_node(value), true);
    }
  }
}

// --sweep KEY=V1,V2,...: [sweep] "KEY" = [V1, V2, ...]. Each value is a TOML
// value or, failing that, a bare string; KEY=[...] takes a TOML array as it is.
// A range A:B:S (Hydra's habit, with ggk's inclusive end): A, A + S, ... up to
// B, integers when all three are, else floats (A + i S, i = 0, 1, ...; B is
// reached within 1e-9 of a step). nullopt when `values` is not of that form.
std::optional<toml::array> sweep_range(const std::string& values, const std::string& source) {
  const std::size_t first = values.find(':');
  const std::size_t second = first == std::string::npos ? first : values.find(':', first + 1);
  if (second == std::string::npos || values.find(':', second + 1) != std::string::npos ||
      values.find_first_of(",[\"'") != std::string::npos) {
    return std::nullopt;
  }
  const std::string parts[3] = {values.substr(0, first),
                                values.substr(first + 1, second - first - 1),
                                values.substr(second + 1)};
  const auto is_integer = [](const std::string& t) {
    return !t.empty() && t.find_first_not_of("+-0123456789") == std::string::npos;
  };
  const std::string usage =
      "a range is START:STOP:STEP with STEP > 0 and STOP >= START, "
      "e.g. --sweep kernels=4:16:4 (4, 8, 12, 16)";
  toml::array array;
  try {
    if (is_integer(parts[0]) && is_integer(parts[1]) && is_integer(parts[2])) {
      const std::int64_t start = std::stoll(parts[0]), stop = std::stoll(parts[1]),
                         step = std::stoll(parts[2]);
      if (step <= 0 || stop < start || (stop - start) / step >= 10'000) {
        throw JobError(source, {}, "", usage + " and at most 10000 values");
      }
      for (std::int64_t v = start; v <= stop; v += step) array.push_back(v);
      return array;
    }
    std::size_t used = 0;
    double numbers[3];
    for (int i = 0; i < 3; ++i) {
      numbers[i] = std::stod(parts[i], &used);
      if (used != parts[i].size()) return std::nullopt;
    }
    const double count = std::floor((numbers[1] - numbers[0]) / numbers[2] + 1e-9);
    if (!(numbers[2] > 0.0) || !(count >= 0.0) || count >= 10'000.0) {
      throw JobError(source, {}, "", usage + " and at most 10000 values");
    }
    for (int i = 0; i <= static_cast<int>(count); ++i) array.push_back(numbers[0] + i * numbers[2]);
    return array;
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  } catch (const std::out_of_range&) {
    throw JobError(source, {}, "", usage + " (a bound is out of range)");
  }
}

void apply_sweep_option(toml::table& root, const std::string& text) {
  const std::string source = "--sweep " + shortened(text);
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size()) {
    throw JobError(source, {}, "",
                   "expected KEY=V1,V2,..., e.g. --sweep kernels=10,20 or "
                   "--sweep khepera.motion.turn_deg=15,30,45");
  }
  const std::string key = text.substr(0, equals);
  const std::string values = text.substr(equals + 1);
  const auto parse_value = [&](const std::string& value) -> toml::table {
    try {
      return toml::parse("x = " + value, std::string_view(source));
    } catch (const toml::parse_error&) {
      try {
        return toml::parse("x = " + toml_literal(value), std::string_view(source));
      } catch (const toml::parse_error& error) {
        throw JobError(source, {}, "",
                       "cannot read the value " + single_quoted(shortened(value)) + ": " +
                           std::string(error.description()));
      }
    }
  };
  toml::array array;
  if (const std::optional<toml::array> range = sweep_range(values, source)) {
    array = *range;
  } else if (values.front() == '[') {
    toml::table parsed = parse_value(values);
    const toml::array* given = parsed.get_as<toml::array>("x");
    if (given == nullptr) throw JobError(source, {}, "", "expected KEY=[V1, V2, ...]");
    array = *given;
  } else {
    std::size_t begin = 0;
    while (begin <= values.size()) {
      const std::size_t comma = std::min(values.find(',', begin), values.size());
      const std::string value = values.substr(begin, comma - begin);
      if (value.empty()) throw JobError(source, {}, "", "an empty value between commas");
      toml::table parsed = parse_value(value);
      array.push_back(*parsed.get("x"));
      begin = comma + 1;
    }
  }
  // Checked here, where the option can be named: a copied array loses where
  // its values came from, so the study's check would blame the job file.
  for (const toml::node& element : array) {
    if (!(element.is_number() || element.is_string() || element.is_boolean())) {
      throw JobError(source, {}, "sweep.\"" + key + "\"",
                     "a study axis takes scalar values (numbers, strings, booleans), got " +
                         describe_value(element));
    }
  }
  toml::node* sweep = root.get("sweep");
  if (sweep == nullptr) {
    root.insert("sweep", toml::table{});
    sweep = root.get("sweep");
  }
  if (!sweep->is_table()) throw JobError(source, {}, "sweep", "the job's sweep is not a table");
  sweep->as_table()->insert_or_assign(key, std::move(array));
}

}  // namespace

std::optional<std::string> results_extension_problem(const std::filesystem::path& file) {
  const std::string extension = file.extension().string();
  if (extension == ".h5" || extension == ".hdf5") return std::nullopt;
  return single_quoted(shortened(file.string())) +
         " is not a results file name: ggk writes HDF5, named *.h5 or *.hdf5 (for CSV, "
         "`ggk info --csv FILE.h5` prints the summary)";
}

toml::table parse_job_toml(std::string_view toml_text, const std::string& file,
                           const JobLoadOptions& options) {
  toml::table root;
  try {
    root = toml::parse(toml_text, std::string_view(file));
  } catch (const toml::parse_error& error) {
    throw JobError(file, location_of(error.source()), "",
                   "TOML syntax error: " + std::string(error.description()));
  }
  for (const std::string& override_text : options.overrides) apply_override(root, override_text);
  std::set<std::string> swept;  // a key given twice is a mistake, not a replacement
  for (const std::string& sweep_text : options.sweeps) {
    const std::string key = sweep_text.substr(0, sweep_text.find('='));
    if (!swept.insert(key).second) {
      throw JobError("--sweep " + shortened(sweep_text), {}, "",
                     "the key " + single_quoted(key) +
                         " is swept twice; give its values in one --sweep (KEY=V1,V2,...)");
    }
    apply_sweep_option(root, sweep_text);
  }
  return root;
}

std::string job_source_text(std::string toml_text, const toml::table& root, const std::string& file,
                            const JobLoadOptions& options) {
  if (options.overrides.empty() && options.sweeps.empty()) return toml_text;
  // What runs is the job the options make: recorded, and compared by --resume.
  std::ostringstream text;
  text << "# " << file << " with";
  for (const std::string& override_text : options.overrides) text << " --set " << override_text;
  for (const std::string& sweep_text : options.sweeps) text << " --sweep " << sweep_text;
  text << "\n" << toml::toml_formatter(root) << "\n";
  return text.str();
}

JobSpec parse_job_table(const toml::table& root, std::string source_text,
                        const std::filesystem::path& source_file, std::span<const TaskTable> tasks,
                        const JobLoadOptions& options) {
  const std::string file = source_file.string();
  const std::vector<std::string_view> keys = top_level_keys(tasks);
  const std::span<const std::string_view> task_names(keys.begin() + kCommonTopLevelKeys.size(),
                                                     keys.end());
  TomlTableReader job(root, "", file, keys);
  const auto resolved = std::make_shared<ResolvedConfig>();
  job.record_into(resolved);

  JobSpec spec;
  spec.name = job.string("name");
  if (!is_valid_name(spec.name)) {
    job.fail("name", "expected letters, digits, '_' or '-' only (it names output files), got \"" +
                         shortened(spec.name) + "\"");
  }
  if (spec.name.size() > kMaxNameCharacters) {
    job.fail("name", "expected at most " + std::to_string(kMaxNameCharacters) +
                         " characters (it names the default output file, results/<name>.h5), got " +
                         std::to_string(spec.name.size()) + " characters");
  }
  spec.task = job.choice("task", task_names);
  spec.runs = static_cast<std::int32_t>(job.integer("runs", {1, kInt32Max}));
  spec.seed = static_cast<std::uint64_t>(
      job.integer("seed", {0, std::numeric_limits<std::int64_t>::max()}));
  spec.sweep = parse_sweep(job);

  const std::filesystem::path job_dir = source_file.parent_path();
  for (const TaskTable& task : tasks) {
    if (task.name == spec.task) {
      spec.task_config = task.parse(job, job_dir, spec.inputs);
    } else if (job.has(task.name)) {
      job.fail(task.name, "table [" + std::string(task.name) + "] belongs to task '" +
                              std::string(task.name) + "', but task = \"" + spec.task + "\"");
    }
  }

  spec.basis = parse_basis(job);
  // Without "pvf" and without [pvf], no pvf.* key is recorded: the job's resolved
  // configuration stays that of a ggk without the basis (--resume, merge).
  if (job.has("pvf") || std::find(spec.sweep.basis.begin(), spec.sweep.basis.end(),
                                  KernelType::pvf) != spec.sweep.basis.end()) {
    spec.pvf = parse_pvf(job);
  }
  spec.lspi = parse_lspi(job);
  spec.output = parse_output(job, spec.name, options);
  spec.adaptive = parse_adaptive_table(job, spec.runs);
  spec.source_file = source_file;
  record_unread_keys(root, "", *resolved);
  spec.resolved = *resolved;
  spec.overrides = options.overrides;
  spec.sweeps = options.sweeps;
  spec.source_text = std::move(source_text);
  return spec;
}

JobSpec parse_job(std::string toml_text, const std::filesystem::path& source_file,
                  std::span<const TaskTable> tasks, const JobLoadOptions& options) {
  Study study = parse_study(std::move(toml_text), source_file, tasks, options);
  if (study.has_axes()) {
    const std::string& axis = study.axes.front().keys.front();
    throw JobError(source_file.string(), {}, "sweep." + axis,
                   "this job is a study (its [sweep] varies " + single_quoted(axis) +
                       "), which this command does not take");
  }
  return std::move(study.configurations.front().job);
}

std::string read_job_file(const std::filesystem::path& path) {
  RegularFileText file = read_regular_file(path);
  if (!file.problem.empty()) {
    throw JobError(path.string(), {}, "", "cannot read the job file: it " + file.problem);
  }
  return std::move(file.text);
}

JobSpec load_job_file(const std::filesystem::path& path, std::span<const TaskTable> tasks,
                      const JobLoadOptions& options) {
  return parse_job(read_job_file(path), path, tasks, options);
}

}  // namespace ggk::engine
