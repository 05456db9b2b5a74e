#include "kernels/confidence_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

namespace ggk::kernels {

ConfidenceSequence confidence_sequence(std::span<const double> values, double low, double high,
                                       double level) {
  if (!std::isfinite(low) || !std::isfinite(high) || !(low < high)) {
    throw std::invalid_argument("confidence_sequence: the bounds must be finite with low < high");
  }
  if (!(level > 0.0 && level < 1.0)) {
    throw std::invalid_argument("confidence_sequence: level must be in (0, 1)");
  }
  const double range = high - low;
  const double log_term = std::log(2.0 / (1.0 - level));
  ConfidenceSequence cs;
  cs.lower.reserve(values.size());
  cs.upper.reserve(values.size());
  double sum_y = 0.0, sum_squares = 0.0;        // of y_i and (y_i - mu_i)^2
  double sum_lambda = 0.0, sum_lambda_y = 0.0;  // of lambda_i and lambda_i y_i
  double sum_penalty = 0.0;                     // of v_i psi(lambda_i)
  double mu_before = 0.5, s2_before = 0.25;     // mu_{t-1}, s2_{t-1}
  double lower = 0.0, upper = 1.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double x = values[i];
    if (!std::isfinite(x) || x < low || x > high) {
      throw std::invalid_argument("confidence_sequence: value " + std::to_string(i) + " (" +
                                  std::to_string(x) + ") lies outside [" + std::to_string(low) +
                                  ", " + std::to_string(high) + "]");
    }
    const double y = (x - low) / range;
    const double t = static_cast<double>(i + 1);
    const double lambda =
        std::min(std::sqrt(2.0 * log_term / (s2_before * t * std::log(1.0 + t))), 0.5);
    const double v = 4.0 * (y - mu_before) * (y - mu_before);
    sum_penalty += v * (-std::log(1.0 - lambda) - lambda) / 4.0;
    sum_lambda += lambda;
    sum_lambda_y += lambda * y;
    const double centre = sum_lambda_y / sum_lambda;
    const double radius = (log_term + sum_penalty) / sum_lambda;
    lower = std::max(lower, centre - radius);
    upper = std::min(upper, centre + radius);
    cs.lower.push_back(low + range * lower);
    cs.upper.push_back(low + range * upper);
    // The estimates after y_t, for the next step.
    sum_y += y;
    const double mu = (0.5 + sum_y) / (t + 1.0);
    sum_squares += (y - mu) * (y - mu);
    mu_before = mu;
    s2_before = (0.25 + sum_squares) / (t + 1.0);
  }
  return cs;
}

ConfidenceSequence asymptotic_confidence_sequence(std::span<const double> values, double level,
                                                  std::int64_t horizon) {
  if (!(level > 0.0 && level < 1.0)) {
    throw std::invalid_argument("asymptotic_confidence_sequence: level must be in (0, 1)");
  }
  if (horizon < 1) {
    throw std::invalid_argument("asymptotic_confidence_sequence: the horizon must be at least 1");
  }
  const double alpha = 1.0 - level;
  const double rho2 = (-2.0 * std::log(alpha) + std::log(-2.0 * std::log(alpha) + 1.0)) /
                      static_cast<double>(horizon);
  const double z = boost::math::quantile(boost::math::normal(), 1.0 - alpha / 2.0);
  const double infinity = std::numeric_limits<double>::infinity();
  ConfidenceSequence cs;
  cs.lower.reserve(values.size());
  cs.upper.reserve(values.size());
  double mean = 0.0, squares = 0.0;  // Welford: the mean and sum of squared deviations
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double x = values[i];
    if (!std::isfinite(x)) {
      throw std::invalid_argument("asymptotic_confidence_sequence: value " + std::to_string(i) +
                                  " is not finite");
    }
    const double t = static_cast<double>(i + 1);
    const double delta = x - mean;
    mean += delta / t;
    squares += delta * (x - mean);
    if (i == 0) {
      cs.lower.push_back(-infinity);
      cs.upper.push_back(infinity);
      continue;
    }
    const double sd = std::sqrt(squares / (t - 1.0));
    const double q = boost::math::quantile(boost::math::students_t(t - 1.0), 1.0 - alpha / 2.0);
    const double half = sd *
                        std::sqrt(2.0 * (t * rho2 + 1.0) / (t * t * rho2) *
                                  std::log(std::sqrt(t * rho2 + 1.0) / alpha)) *
                        q / z;
    cs.lower.push_back(mean - half);
    cs.upper.push_back(mean + half);
  }
  return cs;
}

}  // namespace ggk::kernels
