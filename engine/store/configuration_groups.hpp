#pragma once
// A study's configuration groups in a results file (/<task>/config_NNN, each
// naming its configuration by the attribute study_values): found and matched to
// a study's configurations, and aligned to a grown study's numbering. The
// groups' own attributes are run_store.hpp's (write_configuration_group).

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/study.hpp"

namespace ggk::engine {

// A configuration group of the file, by name under /<task>, and the index of the
// study's configuration with its values.
struct ConfigurationGroup {
  std::string name;
  std::size_t configuration = 0;
};

// A group on its way to a new name (align_configurations renumbers in two steps):
// "moving_config_007".
inline constexpr std::string_view kMovingPrefix = "moving_";

// The file's configuration groups (also those caught on their way to a new name),
// matched to the study's configurations by their values; a UsageError for a
// group of a configuration the study lacks or two groups of one. Empty for a
// plain job's file.
std::vector<ConfigurationGroup> configuration_groups(const Hdf5File& file, const Study& study,
                                                     const std::filesystem::path& output);

// Writes the group of `configuration` with its attributes (its index and values).
void write_configuration_group(Hdf5File& file, const RunConfiguration& configuration);

// Gives every configuration group of the file the name and index of the
// study's configuration with its values (attribute study_values, which names
// a group's configuration whatever its name): a grown study renumbers them
// (its product order changes). In two steps, each group first out of the way
// as "moving_config_NNN" (its new name), so that no move meets a name in use;
// a kill in between leaves groups that the next resume finds by their values
// the same way. Creates the groups of configurations the file lacks.
void align_configurations(Hdf5File& file, const Study& study, const std::filesystem::path& output);

}  // namespace ggk::engine
