#pragma once
// The IR proximity sensor model (DESIGN.md sec. 3; the published parameters of a
// widely used Khepera simulator). Each sensor casts three rays from its mounting
// point: one along its heading (distance dC) and one `side_ray_deg` to either side
// (dL counter-clockwise, dR clockwise). One ray at distance x responds
//
//   F(x) = m (c - x0^2) / (x^2 - 2 x0 x + c)   for x <= range,  F(x) = 0 beyond,
//
// a smooth fall-off from F(0) = m (c - x0^2) / c (1061 with the defaults, above the
// 1023 ceiling) to F(10) = 59. The sensor reads
//
//   r = F(dL) + F(dC) + F(dR) - 2 F(dC / cos(side_ray_deg)),
//
// plus noise (below), clamped to [0, max_reading]. The subtracted term is what
// the two side rays would see if the surface were a flat wall square to the
// centre ray (they would hit it at dC / cos(side)): so a flat wall faced
// squarely reads exactly F(dC), a wall at an angle reads more (the nearer side
// ray gains more than the farther one loses), and an object seen by a side ray
// alone (a corner, an edge off-axis) adds its F. A narrow object that only the
// centre ray hits reads below F(dC), usually 0 after clamping: the model assumes
// surfaces wider than the ray fan.
//
// Noise (SensorNoiseModel), with z one standard normal per sensor and reading:
//   proportional (default)  r = clamp(max(F, 0) (1 + noise_fraction z), 0, max_reading):
//                           the sd is a fraction of the noiseless response (the
//                           convention of Webots' DistanceSensor lookup tables,
//                           whose noise column is a fraction of the value; Enki's
//                           2008 Khepera multiplied each reading by U[0.93, 1.07),
//                           sd 0.040). A sensor that sees nothing reads exactly 0,
//                           as the paper states (sec. 4.2: "at least one of the
//                           sensor values is always zero").
//   threshold               r = F + noise_sd z, then 0 when r < detection_threshold,
//                           else clamped: additive noise behind a detection
//                           threshold; nothing in range reads 0 unless the noise
//                           alone exceeds the threshold (P = 0.13 % at 3 sd).
//   additive                r = clamp(F + noise_sd z, 0, max_reading) (the newer
//                           Enki's IRSensor): a sensor that sees nothing reads
//                           max(0, noise_sd z), above 0 half of the time.
// sims/khepera/README.md says why proportional is the default.
//
// Thread-safety: plain data and a const function object.

namespace ggk::sims::khepera {

enum class SensorNoiseModel { proportional, threshold, additive };

struct SensorModel {
  double range = 10.0;         // cm, > 0; rays see no farther
  double side_ray_deg = 15.0;  // [0, 90); the two side rays' angle to the centre ray
  double response_m = 1200.0;  // m of F, > 0
  double response_x0 = -0.9;   // x0 of F, cm
  double response_c = 7.0;     // c of F, cm^2, > x0^2 (so F is finite and > 0 on [0, range])
  SensorNoiseModel noise_model = SensorNoiseModel::proportional;
  double noise_fraction = 0.04;       // proportional: >= 0; sd / noiseless reading
  double noise_sd = 20.0;             // threshold, additive: >= 0; sd of the added noise
  double detection_threshold = 60.0;  // threshold: >= 0; a noisy reading below it reads 0
  double max_reading = 1023.0;        // > 0; readings are clamped to [0, max_reading]
  friend bool operator==(const SensorModel&, const SensorModel&) = default;
};

// Whether the model draws a normal per sensor and reading (its noise level > 0).
bool draws_noise(const SensorModel& model);

// The reading of a sensor whose noiseless, unclamped response is `noiseless`,
// with the standard normal `z` (0 when !draws_noise(model): the threshold
// model's threshold still applies then).
double noisy_reading(const SensorModel& model, double noiseless, double z);

// "proportional", "threshold", "additive".
const char* to_string(SensorNoiseModel model);

// F and the three-ray combination with the model's constants folded.
class IrResponse {
 public:
  explicit IrResponse(const SensorModel& model);

  // F(distance); 0 for distance > range (and for +infinity: no hit).
  double operator()(double distance) const {
    if (!(distance <= range_)) return 0.0;
    return numerator_ / (distance * distance - 2.0 * x0_ * distance + c_);
  }

  // The noiseless, unclamped reading from the three ray distances (+infinity
  // where a ray hits nothing within range).
  double reading(double left, double centre, double right) const {
    return (*this)(left) + (*this)(centre) +
           (*this)(right)-2.0 * (*this)(centre * inverse_cos_side_);
  }

 private:
  double range_;
  double x0_;
  double c_;
  double numerator_;  // m (c - x0^2)
  double inverse_cos_side_;
};

}  // namespace ggk::sims::khepera
