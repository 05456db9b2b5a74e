#pragma once
// Batch self-organising map (Kohonen) on a rectangular grid: discretises continuous
// states into units whose prototypes become graph nodes (paper sec. 4.2: 20,000
// Khepera IR readings, 24 x 29 = 696 units, about 5 sqrt(n)).
//
// Grid: unit u sits at (row, col) = (u / cols, u % cols), unit spacing; the
// neighbourhood of radius sigma is h(k, u) = exp(-|g_k - g_u|^2 / (2 sigma^2)).
// Batch rule, one epoch: every sample goes to its best-matching unit (BMU), then
//   m_k = sum_u h(k, u) S_u / sum_u h(k, u) n_u,
// with S_u, n_u the sum and count of the samples whose BMU is u. A unit whose
// neighbourhood mass sum_u h(k, u) n_u is zero (or underflows) keeps its prototype.
// The radius shrinks from initial_radius to final_radius over the epochs,
// exponentially (sigma_t = s0 (s1 / s0)^(t / (E - 1))) or linearly; one epoch uses
// final_radius.
//
// BMU: the unit with the smallest squared Euclidean distance, ties to the lowest
// unit id; distances are summed over dimensions in order, so they equal a naive
// loop bit for bit.
//
// Determinism: training uses no random numbers unless initialization is
// random_samples (then only the given stream). BMUs are computed in parallel
// (oneTBB, in the caller's arena) but each is independent, and every sum runs in
// a fixed order, so the map is bit-identical for any thread count.
//
// Thread-safety: SelfOrganizingMap is immutable after construction; share freely
// (best_matching_unit(s) may be called concurrently). train_self_organizing_map is
// reentrant; distinct calls may run in parallel (each with its own RandomStream).

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::kernels {

struct SomGrid {
  std::int32_t rows = 0;
  std::int32_t cols = 0;
  std::int32_t units() const { return rows * cols; }
};

// Map size by the SOM Toolbox rule (Vesanto et al.; the paper's ref. [8]):
// units = round(5 sqrt(n)), at most n; the sides follow the ratio of the two
// largest principal components' standard deviations (Kohonen's rule):
//   rows = round(sqrt(units / ratio)), cols = round(units / rows),
// swapped so that rows <= cols and clamped so that rows * cols <= n.
// aspect_ratio >= 1 (1 = near-square). For n = 20,000 (707 units) any ratio in
// about [1.18, 1.28] gives the paper's 24 x 29; the near-square grid is 26 x 27.
// Throws std::invalid_argument when n < 1 or aspect_ratio is not >= 1.
SomGrid som_grid_for(std::int64_t num_samples, double aspect_ratio = 1.0);

// As above with the ratio measured on the samples (N x d). Falls back to
// near-square, as the SOM Toolbox does, when d < 2, the second variance is zero,
// or lambda_1 / lambda_2 exceeds the unit count (nearly 1-D data).
SomGrid som_grid_for(const Eigen::Ref<const RowMatrixXd>& samples);

// sqrt(lambda_1 / lambda_2) of the sample covariance (>= 1), or 1 for the fallback
// cases above. units is the intended unit count (for the 1-D test).
double som_aspect_ratio(const Eigen::Ref<const RowMatrixXd>& samples, std::int64_t units);

enum class SomRadiusSchedule { exponential, linear };

enum class SomInitialization {
  // Deterministic (no random numbers): the grid spans +/- one standard deviation
  // along the two leading principal components, the longer grid side along the
  // first, around the sample mean (SOM Toolbox's som_lininit).
  principal_components,
  // rows * cols distinct samples drawn with the given RandomStream.
  random_samples,
};

struct SomOptions {
  std::int32_t rows = 24;  // the paper's Khepera map
  std::int32_t cols = 29;
  std::int32_t epochs = 30;
  std::optional<double> initial_radius;  // unset: max(max(rows, cols) / 2, final_radius)
  double final_radius = 1.0;             // > 0, <= initial_radius
  SomRadiusSchedule radius_schedule = SomRadiusSchedule::exponential;
  SomInitialization initialization = SomInitialization::principal_components;
};

struct BestMatch {
  std::int32_t unit = 0;
  double distance = 0.0;  // Euclidean
};

struct BestMatches {
  std::vector<std::int32_t> units;  // one per query row
  std::vector<double> distances;    // Euclidean, one per query row
};

class SelfOrganizingMap {
 public:
  // prototypes: (rows * cols) x d, row u = unit u. quantization_errors and radii
  // are the training history (empty for a map built from given prototypes).
  // Throws std::invalid_argument on a bad grid, a shape mismatch or a non-finite
  // prototype.
  SelfOrganizingMap(std::int32_t rows, std::int32_t cols, RowMatrixXd prototypes,
                    std::vector<double> quantization_errors = {}, std::vector<double> radii = {});

  std::int32_t rows() const { return rows_; }
  std::int32_t cols() const { return cols_; }
  std::int32_t num_units() const { return rows_ * cols_; }
  std::int32_t dimension() const { return static_cast<std::int32_t>(prototypes_.cols()); }
  const RowMatrixXd& prototypes() const { return prototypes_; }

  std::int32_t unit_row(std::int32_t unit) const { return unit / cols_; }
  std::int32_t unit_col(std::int32_t unit) const { return unit % cols_; }
  std::int32_t unit_at(std::int32_t row, std::int32_t col) const { return row * cols_ + col; }
  // units x 2: (row, col) of every unit, as doubles (for plots and grid distances).
  RowMatrixXd grid_coordinates() const;

  // Per epoch, the mean Euclidean distance of the training samples to their BMU
  // after that epoch's update; and the radius that epoch used.
  const std::vector<double>& quantization_errors() const { return quantization_errors_; }
  const std::vector<double>& radii() const { return radii_; }

  // x has dimension() entries. Throws std::invalid_argument on a size mismatch or
  // a non-finite entry.
  BestMatch best_matching_unit(std::span<const double> x) const;
  // One BMU per row of queries (M x d), in parallel over rows (oneTBB).
  BestMatches best_matching_units(const Eigen::Ref<const RowMatrixXd>& queries) const;

 private:
  std::int32_t rows_;
  std::int32_t cols_;
  RowMatrixXd prototypes_;
  // d x padded_units copy of the prototypes (dimension-major) for the BMU loop.
  std::vector<double> prototypes_by_dimension_;
  std::vector<double> quantization_errors_;
  std::vector<double> radii_;
};

// Trains a batch SOM on samples (N x d, finite). Throws std::invalid_argument on
// bad options (empty grid, epochs < 1, radii not 0 < final <= initial), more units
// than samples, empty or non-finite samples, or random_samples initialisation
// without a stream (random is ignored otherwise).
SelfOrganizingMap train_self_organizing_map(const Eigen::Ref<const RowMatrixXd>& samples,
                                            const SomOptions& options,
                                            RandomStream* random = nullptr);

}  // namespace ggk::kernels
