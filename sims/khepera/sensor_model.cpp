#include "sims/khepera/sensor_model.hpp"

#include <cmath>

#include "sims/khepera/pose.hpp"

namespace ggk::sims::khepera {

IrResponse::IrResponse(const SensorModel& model)
    : range_(model.range),
      x0_(model.response_x0),
      c_(model.response_c),
      numerator_(model.response_m * (model.response_c - model.response_x0 * model.response_x0)),
      inverse_cos_side_(1.0 / std::cos(degrees_to_radians(model.side_ray_deg))) {}

}  // namespace ggk::sims::khepera
