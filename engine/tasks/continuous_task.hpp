#pragma once
// The TaskDefinition of a continuous task (continuous_protocol.hpp) from its
// parts, so that a task file holds only what is its own: its table parser, its
// environment and its memory sizes.
//
//   Parse(job, job_dir) -> Config        reads the task's table; Config has a
//                                        ContinuousProtocol member `protocol`
//   Environment(const Config&) -> ContinuousEnvironment
//                                        valid while the Config lives (the job
//                                        holds it for the whole run)
//   Sizes(const Config&) -> ContinuousSizes
//
// The Khepera builds its own (its parser also reads an arena file).

#include <any>
#include <filesystem>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

template <auto Parse, auto Environment, auto Sizes>
TaskDefinition continuous_task_definition(std::string_view name) {
  using Config = std::decay_t<decltype(Parse(std::declval<const TomlTableReader&>(),
                                             std::declval<const std::filesystem::path&>()))>;
  return {{name,
           [](const TomlTableReader& job, const std::filesystem::path& job_dir,
              std::vector<JobInput>&) -> std::any { return Parse(job, job_dir); }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            const auto& config = task_config_as<Config>(job);
            return run_continuous_protocol(Environment(config), config.protocol, job, run, points);
          },
          [](const JobSpec& job) {
            const auto& config = task_config_as<Config>(job);
            return estimate_continuous_run(Sizes(config), config.protocol, job);
          },
          [](const JobSpec& job) {
            const auto& config = task_config_as<Config>(job);
            return continuous_metric_specs(Environment(config), config.protocol);
          },
          continuous_dataset_specs()};
}

}  // namespace ggk::engine
