#include "engine/job/kernel_width.hpp"

#include <cstdio>
#include <optional>

#include "engine/job/sweep.hpp"
#include "kernels/gaussian_kernels.hpp"

namespace ggk::engine {
namespace {

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

// Why `sigma` cannot work at `scale`, or nothing.
std::optional<std::string> width_problem(double sigma, const std::string& shown,
                                         const DistanceScale& scale) {
  // Widths that keep exp's argument within the normal doubles at the smallest
  // distance (|x| < 708) and away from 1 at the largest (|x| > 1e-15), for the
  // message; the test itself is the exact one.
  const double low = scale.smallest / 37.6;
  const double high = scale.largest * 2.2e7;
  const std::string range = "; widths for this task lie between about " + format_number(low) +
                            " and " + format_number(high);
  if (kernels::gaussian(scale.smallest, sigma) == 0.0) {
    return "sigma = " + shown +
           " is too small for this task's distances: every kernel value between distinct "
           "states underflows to 0 (exp(-d^2 / (2 sigma^2)) = 0 already at d = " +
           format_number(scale.smallest) + ", " + scale.smallest_is +
           "), so the basis would be the centres' indicator functions" + range;
  }
  if (kernels::gaussian(scale.largest, sigma) == 1.0) {
    return "sigma = " + shown +
           " is too large for this task's distances: every kernel value rounds to 1 "
           "(exp(-d^2 / (2 sigma^2)) = 1 even at d = " +
           format_number(scale.largest) + ", " + scale.largest_is +
           "), so the basis would be constant" + range;
  }
  return std::nullopt;
}

}  // namespace

void check_kernel_widths(const TomlTableReader& job, const DistanceScale& scale) {
  const std::optional<TomlTableReader> sweep = job.subtable("sweep", kSweepTableKeys);
  if (!sweep) return;  // parse_job() has refused the job already
  const toml::node* sigma = sweep->find("sigma");
  const toml::array* values = sigma == nullptr ? nullptr : sigma->as_array();
  if (values == nullptr) return;
  for (const toml::node& element : *values) {
    std::optional<double> value;
    if (const auto* integer = element.as_integer()) value = static_cast<double>(integer->get());
    if (const auto* floating = element.as_floating_point()) value = floating->get();
    if (!value) continue;
    if (const auto problem = width_problem(*value, describe_value(element), scale)) {
      sweep->fail_at(element, "sigma", *problem);
    }
  }
}

}  // namespace ggk::engine
