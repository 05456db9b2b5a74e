#pragma once
// The error a bad arm configuration raises (check_geometry, Arm's constructor),
// naming the part of ArmConfig at fault so that the job-file parser can point at
// the key that set it.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ggk::sims::arm {

enum class ArmConfigField {
  links,            // link lengths
  base,             // base position
  shoulder_limits,  // JointLimits::shoulder_*
  elbow_limits,     // JointLimits::elbow_*
  grid_step,        // ArmConfig::grid_step_tenths
  obstacles,        // one obstacle (index()) or, with index() == -1, all of them
  object,
  start_A,
};

class ArmConfigError : public std::invalid_argument {
 public:
  ArmConfigError(ArmConfigField field, std::int32_t index, const std::string& message)
      : std::invalid_argument(message), field_(field), index_(index) {}
  ArmConfigField field() const { return field_; }
  // The obstacle's index for field() == obstacles, else -1.
  std::int32_t index() const { return index_; }

 private:
  ArmConfigField field_;
  std::int32_t index_;
};

}  // namespace ggk::sims::arm
