#pragma once
// An anytime-valid confidence sequence for the mean of bounded observations: the
// predictable plug-in empirical-Bernstein confidence sequence (PrPl-EB) of
// Waudby-Smith & Ramdas (2023, "Estimating means of bounded random variables by
// betting", JRSS B 86(1), Theorem 2 and eq. (13)-(15)). For an adaptive study it
// bounds the mean paired difference of two configurations over runs.
//
// The guarantee: when x_1, x_2, ... lie in [low, high] and each has conditional
// mean mu given the ones before it (independent runs with a common mean do), then
// P(mu lies outside [lower_t, upper_t] for some t >= 1) <= 1 - level. It holds
// uniformly over t, so it survives looking after every run and stopping on what
// one sees (optional stopping), which a fixed-n interval recomputed after each
// look does not.
//
// With y_i = (x_i - low) / (high - low) in [0, 1], alpha = 1 - level:
//   mu_t     = (1/2 + sum_{i<=t} y_i) / (t + 1),          mu_0 = 1/2
//   s2_t     = (1/4 + sum_{i<=t} (y_i - mu_i)^2) / (t + 1), s2_0 = 1/4
//   lambda_t = min(sqrt(2 log(2/alpha) / (s2_{t-1} t log(1 + t))), 1/2)
//   v_i      = 4 (y_i - mu_{i-1})^2,  psi(l) = (-log(1 - l) - l) / 4
//   centre_t = sum lambda_i y_i / sum lambda_i
//   radius_t = (log(2/alpha) + sum v_i psi(lambda_i)) / sum lambda_i
// and [centre_t - radius_t, centre_t + radius_t], clipped to [0, 1] and
// intersected with every earlier interval (still valid: the intersection over t
// of sets that all hold at once), mapped back to [low, high].
//
// Thread-safety: a pure function.
#include <cstdint>
#include <span>
#include <vector>

namespace ggk::kernels {

struct ConfidenceSequence {
  std::vector<double> lower;  // after each prefix x_1 .. x_t, t = 1 .. n
  std::vector<double> upper;
};

// Throws std::invalid_argument when low >= high, a bound or value is not finite,
// a value lies outside [low, high], or level is not in (0, 1).
ConfidenceSequence confidence_sequence(std::span<const double> values, double low, double high,
                                       double level);

// The asymptotic confidence sequence (AsympCS) of Waudby-Smith, Arnold, Wu, Chang
// & Ramdas (2024, "Time-uniform central limit theory and asymptotic confidence
// sequences", Ann. Statist. 52(6)), its two-sided normal-mixture boundary with
// the variance estimated: no range needed, for means whose
// range is wide against their spread, where the bounded sequence above pays
// for the range (its radius is at least 2 log(2 / alpha) / t of it). With
// alpha = 1 - level, rho^2 = (-2 log alpha + log(-2 log alpha + 1)) / horizon
// (the tightest at t = horizon, the most runs a cell gets), the sample mean m_t
// and standard deviation s_t (divisor t - 1):
//   m_t -+ s_t sqrt(2 (t rho^2 + 1) / (t^2 rho^2) log(sqrt(t rho^2 + 1) / alpha))
//         * q_t / z,
// where q_t / z, Student's t quantile 1 - alpha/2 at t - 1 degrees of freedom over
// the normal one, widens it at small t as Student's t widens the z interval
// (ggk's addition: tests/python/test_confidence_sequence.py measures both ways).
// Bounds after the first value are infinite. Not intersected over t.
//
// The guarantee is asymptotic, as a t interval's is: coverage at every t at once
// tends to `level` as the start time grows, for any distribution with a finite
// variance; at small t and for skewed values it can fall short (the simulation
// gives the numbers). Throws std::invalid_argument for a value that is not
// finite, a level outside (0, 1) or a horizon below 1.
ConfidenceSequence asymptotic_confidence_sequence(std::span<const double> values, double level,
                                                  std::int64_t horizon);

}  // namespace ggk::kernels
