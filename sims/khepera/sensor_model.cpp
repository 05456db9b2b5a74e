#include "sims/khepera/sensor_model.hpp"

#include <algorithm>
#include <cmath>

#include "sims/khepera/pose.hpp"

namespace ggk::sims::khepera {

IrResponse::IrResponse(const SensorModel& model)
    : range_(model.range),
      x0_(model.response_x0),
      c_(model.response_c),
      numerator_(model.response_m * (model.response_c - model.response_x0 * model.response_x0)),
      inverse_cos_side_(1.0 / std::cos(degrees_to_radians(model.side_ray_deg))) {}

bool draws_noise(const SensorModel& model) {
  return model.noise_model == SensorNoiseModel::proportional ? model.noise_fraction > 0.0
                                                             : model.noise_sd > 0.0;
}

double noisy_reading(const SensorModel& model, double noiseless, double z) {
  const double max_reading = model.max_reading;
  switch (model.noise_model) {
    case SensorNoiseModel::proportional:
      // A negative noiseless response (a post only the centre ray sees) is no
      // response: 0, and so is its noise.
      return std::clamp(std::max(noiseless, 0.0) * (1.0 + model.noise_fraction * z), 0.0,
                        max_reading);
    case SensorNoiseModel::threshold: {
      const double value = noiseless + model.noise_sd * z;
      return value < model.detection_threshold ? 0.0 : std::clamp(value, 0.0, max_reading);
    }
    case SensorNoiseModel::additive:
      break;
  }
  return std::clamp(noiseless + model.noise_sd * z, 0.0, max_reading);
}

const char* to_string(SensorNoiseModel model) {
  switch (model) {
    case SensorNoiseModel::proportional:
      return "proportional";
    case SensorNoiseModel::threshold:
      return "threshold";
    case SensorNoiseModel::additive:
      return "additive";
  }
  return "additive";
}

}  // namespace ggk::sims::khepera
