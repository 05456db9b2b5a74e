#pragma once
// The Khepera navigation MDP (paper sec. 4.2): a Khepera I in a walled arena with
// obstacles; state = its 8 IR readings in [0, max_reading]; four actions
// (motion.hpp); reward +1 for a forward step, -2 for a collision (the step is
// undone), 0 otherwise. The simulator is the pose dynamics; the protocol sees
// only readings.
//
// One step from pose p with action a, drawing from the caller's stream in this
// order: the left then the right wheel factor (two uniforms; none when
// wheel_noise == 0), then one normal per sensor s0..s7 (none when the sensor
// model's noise level is 0: draws_noise in sensor_model.hpp).
// The wheels roll command x factor along an exact differential-drive arc; the
// body is tested at motion.collision_substeps points along it; the first overlap
// undoes the whole step (next pose = p, collided, reward rewards.collision). The
// observation is sensed at the next pose.
//
// Thread-safety: immutable after construction; every random number comes from
// the stream passed in, so any number of threads may step one Khepera with
// their own streams, with results independent of the thread count.

#include <array>
#include <cstdint>

#include "kernels/random_stream.hpp"
#include "sims/khepera/khepera_config.hpp"
#include "sims/khepera/khepera_config_error.hpp"
#include "sims/khepera/world.hpp"

namespace ggk::sims::khepera {

// Readings of s0..s7.
using Readings = std::array<double, kNumSensors>;

// The three ray distances of one sensor (cm, kNoHit beyond range).
struct SensorRays {
  double left = kNoHit;  // side_ray_deg counter-clockwise of the sensor's heading
  double centre = kNoHit;
  double right = kNoHit;
};

struct StepResult {
  Readings observation{};  // sensed at next_pose, with noise
  Pose next_pose;          // the start pose again after a collision
  double reward = 0.0;
  bool collided = false;
};

class Khepera {
 public:
  // Throws KheperaConfigError (check_config, and field start when the body
  // overlaps a wall or an obstacle at the start pose).
  explicit Khepera(KheperaConfig config);

  const KheperaConfig& config() const { return config_; }
  const World& world() const { return world_; }
  // The evaluation start pose (heading wrapped into [-pi, pi)).
  Pose start_pose() const { return start_pose_; }
  std::int32_t num_actions() const { return kNumActions; }
  std::int32_t num_sensors() const { return kNumSensors; }

  // Whether the body at `pose` overlaps a wall or an obstacle.
  bool collides(const Pose& pose) const;

  // The rays of sensor `sensor` (0..7; throws std::out_of_range otherwise).
  SensorRays sensor_rays(const Pose& pose, std::int32_t sensor) const;
  // Readings without noise, clamped to [0, max_reading].
  Readings sense_noiseless(const Pose& pose) const;
  // Readings with the sensor model's noise (one normal per sensor), clamped.
  Readings sense(const Pose& pose, kernels::RandomStream& random) const;

  // One control step from a collision-free `pose`. Throws std::out_of_range for a
  // bad action.
  StepResult step(const Pose& pose, std::int32_t action, kernels::RandomStream& random) const;

  // A pose uniform over the collision-free part of the arena's box (centre
  // uniform by rejection, heading uniform in [-pi, pi)); three uniforms per try.
  // Throws std::runtime_error after a million rejected tries.
  Pose sample_free_pose(kernels::RandomStream& random) const;

 private:
  struct SensorGeometry {
    Point2 mount;                // robot frame
    std::array<Point2, 3> rays;  // unit directions, robot frame: left, centre, right
  };

  // The left, centre and right ray distances of `sensor` from the body at `center`.
  std::array<double, 3> fan_distances(Point2 center, double cos_heading, double sin_heading,
                                      std::int32_t sensor) const;
  double noiseless_reading(Point2 center, double cos_heading, double sin_heading,
                           std::int32_t sensor) const;

  KheperaConfig config_;
  World world_;
  IrResponse response_;
  std::array<SensorGeometry, kNumSensors> sensors_;
  std::array<WheelTravel, kNumActions> commands_;
  Pose start_pose_;
};

}  // namespace ggk::sims::khepera
