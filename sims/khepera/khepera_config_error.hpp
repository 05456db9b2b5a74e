#pragma once
// The error a bad Khepera configuration raises (check_config, Khepera's
// constructor), naming the part of KheperaConfig at fault so that the job-file
// parser can point at the key that set it.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ggk::sims::khepera {

enum class KheperaConfigField {
  body,          // RobotBody::radius, wheel_base
  sensors,       // one IR sensor's mounting (index())
  sensor_model,  // SensorModel
  motion,        // MotionModel
  rewards,       // Rewards
  arena_box,     // Arena::min, max
  obstacles,     // one obstacle (index())
  start,         // Arena::start
  protocol,      // series, steps_per_series, test_max_steps, test_episodes
};

class KheperaConfigError : public std::invalid_argument {
 public:
  KheperaConfigError(KheperaConfigField field, std::int32_t index, const std::string& message)
      : std::invalid_argument(message), field_(field), index_(index) {}
  KheperaConfigField field() const { return field_; }
  // The sensor's index for field() == sensors, the obstacle's for obstacles, else -1.
  std::int32_t index() const { return index_; }

 private:
  KheperaConfigField field_;
  std::int32_t index_;
};

}  // namespace ggk::sims::khepera
