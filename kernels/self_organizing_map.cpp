#include "kernels/self_organizing_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "kernels/avx2_dispatch.hpp"

namespace ggk::kernels {

namespace {

// The BMU loop scores units in tiles of kTile: the tile's partial sums stay in
// registers while the d dimensions stream past, and the inner loop over the tile
// vectorises. The table is padded to a whole number of tiles with +inf, whose
// distance is +inf and never wins.
constexpr std::int32_t kTile = 16;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::int32_t padded_units(std::int32_t units) {
  return (units + kTile - 1) / kTile * kTile;
}

// d x padded_units, dimension-major: table[j * stride + u] = prototypes(u, j).
std::vector<double> dimension_major_table(const RowMatrixXd& prototypes) {
  const auto units = static_cast<std::int32_t>(prototypes.rows());
  const auto dim = static_cast<std::int32_t>(prototypes.cols());
  const std::int32_t stride = padded_units(units);
  std::vector<double> table(static_cast<std::size_t>(dim) * stride, kInfinity);
  for (std::int32_t j = 0; j < dim; ++j) {
    for (std::int32_t u = 0; u < units; ++u) {
      table[static_cast<std::size_t>(j) * stride + u] = prototypes(u, j);
    }
  }
  return table;
}

struct SquaredMatch {
  std::int32_t unit;
  double squared_distance;
};

// Brute force over all units. acc[t] sums (x_j - m_j)^2 for j = 0, 1, ..., d - 1 in
// order, exactly as a naive loop does (Eigen's packet ops are the same IEEE
// operations per lane, and nothing is fused), so distances are bit-identical to
// it; ties keep the lowest unit (strict <). The tile is an Eigen array so that
// the loop is vectorised across units, not across the few dimensions.
SquaredMatch best_match_squared(const double* x, const std::vector<double>& table,
                                std::int32_t units, std::int32_t dim) {
  using Tile = Eigen::Array<double, kTile, 1>;
  const std::int32_t stride = padded_units(units);
  double best = kInfinity;
  std::int32_t best_unit = 0;
  for (std::int32_t first = 0; first < units; first += kTile) {
    Tile acc = Tile::Zero();
    for (std::int32_t j = 0; j < dim; ++j) {
      const Eigen::Map<const Tile> column(table.data() + static_cast<std::size_t>(j) * stride +
                                          first);
      acc += (x[j] - column).square();
    }
    // Most tiles hold nothing better than the best so far: test the tile minimum
    // (a vectorised reduction) before looking for the index.
    if (acc.minCoeff() < best) {
      for (std::int32_t t = 0; t < kTile; ++t) {
        if (acc[t] < best) {
          best = acc[t];
          best_unit = first + t;
        }
      }
    }
  }
  return {best_unit, best};
}

#if GGK_AVX2_DISPATCH
// best_match_squared with the tile in four 256-bit registers (the AVX2 path,
// chosen at run time as the batch search's): per lane the same subtraction,
// multiply and add in the same order (no FMA in the target), so the same bits;
// the tile's minimum is exact in any order, and the index search is the same loop.
__attribute__((target("avx2"))) SquaredMatch best_match_squared_avx2(
    const double* x, const std::vector<double>& table, std::int32_t units, std::int32_t dim) {
  static_assert(kTile == 16, "four registers of four units per tile");
  const std::int32_t stride = padded_units(units);
  double best = kInfinity;
  std::int32_t best_unit = 0;
  for (std::int32_t first = 0; first < units; first += kTile) {
    __m256d acc[4] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd(),
                      _mm256_setzero_pd()};
    for (std::int32_t j = 0; j < dim; ++j) {
      const double* column = table.data() + static_cast<std::size_t>(j) * stride + first;
      const __m256d xj = _mm256_set1_pd(x[j]);
      for (int r = 0; r < 4; ++r) {
        const __m256d diff = _mm256_sub_pd(xj, _mm256_loadu_pd(column + 4 * r));
        acc[r] = _mm256_add_pd(acc[r], _mm256_mul_pd(diff, diff));
      }
    }
    alignas(32) double tile[kTile];
    for (int r = 0; r < 4; ++r) _mm256_store_pd(tile + 4 * r, acc[r]);
    const __m256d low = _mm256_min_pd(_mm256_min_pd(acc[0], acc[1]), _mm256_min_pd(acc[2], acc[3]));
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, low);
    if (std::min(std::min(lanes[0], lanes[1]), std::min(lanes[2], lanes[3])) < best) {
      for (std::int32_t t = 0; t < kTile; ++t) {
        if (tile[t] < best) {
          best = tile[t];
          best_unit = first + t;
        }
      }
    }
  }
  return {best_unit, best};
}
#endif

// The batch search screens units through the BLAS and settles on the exact
// distance. For a block of query rows x_i, s(i, u) = |m_u|^2 - 2 x_i . m_u (one GEMM
// for the block) equals |x_i - m_u|^2 - |x_i|^2 up to rounding of at most
// ~(d + 2) eps (|x_i|^2 + |m_u|^2). Every unit whose score is within
// kScreenSlack (|x_i|^2 + max_u |m_u|^2) of the row's smallest score (a slack
// thousands of times that bound) is a candidate; the candidates' distances are then
// computed by the exact loop (the same arithmetic as best_match_squared) and the
// smallest wins, ties to the lowest unit. The exact loop's minimiser is always a
// candidate, so the result equals the brute-force search bit for bit.
constexpr Eigen::Index kQueryBlock = 256;
constexpr double kScreenSlack = 1e-11;

// |x - m_u|^2 summed over dimensions in order (as best_match_squared's lanes).
double exact_squared(const double* x, const std::vector<double>& table, std::int32_t stride,
                     std::int32_t unit, std::int32_t dim) {
  double sum = 0.0;
  for (std::int32_t j = 0; j < dim; ++j) {
    const double diff = x[j] - table[static_cast<std::size_t>(j) * stride + unit];
    sum += diff * diff;
  }
  return sum;
}

// The prototypes back from the dimension-major table (units x d), and their
// squared norms.
struct ScreenTable {
  RowMatrixXd prototypes;
  Eigen::VectorXd squared_norms;
  double max_squared_norm = 0.0;
};

ScreenTable screen_table(const std::vector<double>& table, std::int32_t units, std::int32_t dim) {
  const std::int32_t stride = padded_units(units);
  ScreenTable screen;
  screen.prototypes.resize(units, dim);
  for (std::int32_t u = 0; u < units; ++u) {
    for (std::int32_t j = 0; j < dim; ++j) {
      screen.prototypes(u, j) = table[static_cast<std::size_t>(j) * stride + u];
    }
  }
  screen.squared_norms = screen.prototypes.rowwise().squaredNorm();
  screen.max_squared_norm = units > 0 ? screen.squared_norms.maxCoeff() : 0.0;
  return screen;
}

// BMU of every row of `points`, in parallel over blocks of rows; each row is
// independent, so the result does not depend on the partition or the thread count.
// One query's screen: row[u] = |m_u|^2 - 2 row[u] (row[u] holding x . m_u), and
// the smallest of them. Portable: one unit at a time.
double scan_portable(double* row, const double* squared_norms, std::int32_t units) {
  double lowest = kInfinity;
  for (std::int32_t u = 0; u < units; ++u) {
    row[u] = squared_norms[u] - 2.0 * row[u];
    lowest = std::min(lowest, row[u]);
  }
  return lowest;
}

// Calls candidate(u) for every unit u with row[u] <= limit, in increasing u.
template <class Candidate>
void for_each_candidate_portable(const double* row, std::int32_t units, double limit,
                                 const Candidate& candidate) {
  for (std::int32_t u = 0; u < units; ++u) {
    if (row[u] <= limit) candidate(u);
  }
}

#if GGK_AVX2_DISPATCH
// The same two passes four units at a time (kernels/copy_basis_greedy.hpp: the
// AVX2 path is chosen at run time). Each score is the same IEEE multiply by 2
// (exact) and subtraction; _mm256_min_pd(a, b) is a < b ? a : b, lane by lane, as
// std::min(b, a) is, so the minimum is the portable one whatever the order (the
// screen's scores are finite: the samples are checked finite). The candidates
// are the lanes whose compare holds, visited in increasing u.
__attribute__((target("avx2"))) double scan_avx2(double* row, const double* squared_norms,
                                                 std::int32_t units) {
  __m256d lowest4 = _mm256_set1_pd(kInfinity);
  const __m256d two = _mm256_set1_pd(2.0);
  std::int32_t u = 0;
  for (; u + 4 <= units; u += 4) {
    const __m256d score = _mm256_sub_pd(_mm256_loadu_pd(squared_norms + u),
                                        _mm256_mul_pd(two, _mm256_loadu_pd(row + u)));
    _mm256_storeu_pd(row + u, score);
    lowest4 = _mm256_min_pd(score, lowest4);
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, lowest4);
  double lowest = kInfinity;
  for (const double lane : lanes) lowest = std::min(lowest, lane);
  for (; u < units; ++u) {
    row[u] = squared_norms[u] - 2.0 * row[u];
    lowest = std::min(lowest, row[u]);
  }
  return lowest;
}

// The units' bits of row[u] <= limit (ordered, non-signalling: false for NaN, as
// the portable compare), four at a time.
__attribute__((target("avx2"))) void candidate_masks_avx2(const double* row, std::int32_t units,
                                                          double limit,
                                                          std::vector<std::uint8_t>& masks) {
  const __m256d bound = _mm256_set1_pd(limit);
  masks.assign(static_cast<std::size_t>((units + 3) / 4), 0);
  std::int32_t u = 0;
  for (; u + 4 <= units; u += 4) {
    masks[static_cast<std::size_t>(u / 4)] = static_cast<std::uint8_t>(
        _mm256_movemask_pd(_mm256_cmp_pd(_mm256_loadu_pd(row + u), bound, _CMP_LE_OQ)));
  }
  for (; u < units; ++u) {
    if (row[u] <= limit) masks[static_cast<std::size_t>(u / 4)] |= std::uint8_t(1u << (u % 4));
  }
}
#endif

double scan(double* row, const double* squared_norms, std::int32_t units) {
#if GGK_AVX2_DISPATCH
  if (cpu_has_avx2()) return scan_avx2(row, squared_norms, units);
#endif
  return scan_portable(row, squared_norms, units);
}

template <class Candidate>
void for_each_candidate(const double* row, std::int32_t units, double limit,
                        const Candidate& candidate) {
#if GGK_AVX2_DISPATCH
  if (cpu_has_avx2()) {
    thread_local std::vector<std::uint8_t> masks;
    candidate_masks_avx2(row, units, limit, masks);
    for (std::size_t block = 0; block < masks.size(); ++block) {
      for (std::uint32_t bits = masks[block]; bits != 0; bits &= bits - 1) {
        candidate(static_cast<std::int32_t>(block * 4) + __builtin_ctz(bits));
      }
    }
    return;
  }
#endif
  for_each_candidate_portable(row, units, limit, candidate);
}

void best_matches_squared(const Eigen::Ref<const RowMatrixXd>& points,
                          const std::vector<double>& table, std::int32_t units,
                          std::span<std::int32_t> out_units, std::span<double> out_squared) {
  const auto dim = static_cast<std::int32_t>(points.cols());
  const std::int32_t stride = padded_units(units);
  const ScreenTable screen = screen_table(table, units, dim);
  const Eigen::Index blocks = (points.rows() + kQueryBlock - 1) / kQueryBlock;
  tbb::parallel_for(
      tbb::blocked_range<Eigen::Index>(0, blocks, 1),
      [&](const tbb::blocked_range<Eigen::Index>& range) {
        RowMatrixXd scores;
        for (Eigen::Index block = range.begin(); block != range.end(); ++block) {
          const Eigen::Index first = block * kQueryBlock;
          const Eigen::Index count = std::min(kQueryBlock, points.rows() - first);
          scores.resize(count, units);
          scores.noalias() = points.middleRows(first, count) * screen.prototypes.transpose();
          for (Eigen::Index r = 0; r < count; ++r) {
            const Eigen::Index i = first + r;
            double* row = scores.row(r).data();
            const double lowest = scan(row, screen.squared_norms.data(), units);
            const double* x = points.row(i).data();
            const double limit =
                lowest + kScreenSlack * (points.row(i).squaredNorm() + screen.max_squared_norm);
            double best = kInfinity;
            std::int32_t best_unit = 0;
            for_each_candidate(row, units, limit, [&](std::int32_t u) {
              const double exact = exact_squared(x, table, stride, u, dim);
              if (exact < best) {
                best = exact;
                best_unit = u;
              }
            });
            out_units[static_cast<std::size_t>(i)] = best_unit;
            out_squared[static_cast<std::size_t>(i)] = best;
          }
        }
      });
}

void check_grid(const char* where, std::int32_t rows, std::int32_t cols) {
  if (rows < 1 || cols < 1) {
    throw std::invalid_argument(std::string(where) +
                                ": grid must have at least one row and one "
                                "column, got " +
                                std::to_string(rows) + " x " + std::to_string(cols));
  }
  if (static_cast<std::int64_t>(rows) * cols > std::numeric_limits<std::int32_t>::max()) {
    throw std::invalid_argument(std::string(where) + ": grid " + std::to_string(rows) + " x " +
                                std::to_string(cols) + " has more than 2^31 - 1 units");
  }
}

// Mean and the two leading principal axes (eigenvalues descending, eigenvectors
// with their largest-magnitude entry made positive so that the sign is canonical).
// Sums run over samples in order: deterministic.
struct PrincipalAxes {
  Eigen::VectorXd mean;
  double variance[2] = {0.0, 0.0};
  Eigen::VectorXd axis[2];
};

PrincipalAxes principal_axes(const Eigen::Ref<const RowMatrixXd>& samples) {
  const Eigen::Index n = samples.rows();
  const Eigen::Index d = samples.cols();
  PrincipalAxes result;
  result.mean = Eigen::VectorXd::Zero(d);
  for (Eigen::Index i = 0; i < n; ++i) result.mean += samples.row(i).transpose();
  result.mean /= static_cast<double>(n);
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(d, d);
  Eigen::VectorXd centred(d);
  for (Eigen::Index i = 0; i < n; ++i) {
    centred = samples.row(i).transpose() - result.mean;
    for (Eigen::Index b = 0; b < d; ++b) {
      for (Eigen::Index a = b; a < d; ++a) covariance(a, b) += centred(a) * centred(b);
    }
  }
  if (n > 1) covariance /= static_cast<double>(n - 1);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);  // lower triangle
  for (int k = 0; k < 2; ++k) {
    result.axis[k] = Eigen::VectorXd::Zero(d);
    const Eigen::Index column = d - 1 - k;  // eigenvalues come ascending
    if (column < 0) continue;
    result.variance[k] = std::max(solver.eigenvalues()(column), 0.0);
    Eigen::VectorXd v = solver.eigenvectors().col(column);
    Eigen::Index largest = 0;
    v.cwiseAbs().maxCoeff(&largest);
    if (v(largest) < 0) v = -v;
    result.axis[k] = v;
  }
  return result;
}

void validate_samples(const char* where, const Eigen::Ref<const RowMatrixXd>& samples) {
  if (samples.rows() < 1 || samples.cols() < 1) {
    throw std::invalid_argument(std::string(where) +
                                ": need at least one sample of dimension >= "
                                "1, got " +
                                std::to_string(samples.rows()) + " x " +
                                std::to_string(samples.cols()));
  }
  if (!samples.allFinite()) {
    throw std::invalid_argument(std::string(where) + ": samples contain NaN or infinity");
  }
}

std::int64_t unit_count_for(std::int64_t num_samples) {
  const auto units = std::llround(5.0 * std::sqrt(static_cast<double>(num_samples)));
  return std::clamp<std::int64_t>(
      units, 1, std::min<std::int64_t>(num_samples, std::numeric_limits<std::int32_t>::max()));
}

// Radius per epoch: exponential or linear from s0 to s1; one epoch uses s1.
std::vector<double> radius_schedule(const SomOptions& options, double initial) {
  std::vector<double> radii(static_cast<std::size_t>(options.epochs));
  const double final_radius = options.final_radius;
  for (std::int32_t t = 0; t < options.epochs; ++t) {
    const double fraction =
        options.epochs > 1 ? static_cast<double>(t) / static_cast<double>(options.epochs - 1) : 1.0;
    radii[static_cast<std::size_t>(t)] = options.radius_schedule == SomRadiusSchedule::exponential
                                             ? initial * std::pow(final_radius / initial, fraction)
                                             : initial + (final_radius - initial) * fraction;
  }
  return radii;
}

RowMatrixXd principal_component_prototypes(const Eigen::Ref<const RowMatrixXd>& samples,
                                           std::int32_t rows, std::int32_t cols) {
  const PrincipalAxes axes = principal_axes(samples);
  // The longer grid side follows the first principal component (Kohonen's rule).
  const bool cols_first = cols >= rows;
  const Eigen::VectorXd along_cols =
      std::sqrt(axes.variance[cols_first ? 0 : 1]) * axes.axis[cols_first ? 0 : 1];
  const Eigen::VectorXd along_rows =
      std::sqrt(axes.variance[cols_first ? 1 : 0]) * axes.axis[cols_first ? 1 : 0];
  auto spread = [](std::int32_t index, std::int32_t count) {  // evenly over [-1, 1]
    return count > 1 ? -1.0 + 2.0 * index / static_cast<double>(count - 1) : 0.0;
  };
  RowMatrixXd prototypes(static_cast<Eigen::Index>(rows) * cols, samples.cols());
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      prototypes.row(static_cast<Eigen::Index>(r) * cols + c) =
          (axes.mean + spread(c, cols) * along_cols + spread(r, rows) * along_rows).transpose();
    }
  }
  return prototypes;
}

RowMatrixXd random_sample_prototypes(const Eigen::Ref<const RowMatrixXd>& samples,
                                     std::int32_t units, RandomStream& random) {
  // Partial Fisher-Yates: the first `units` entries become distinct sample indices.
  std::vector<std::int64_t> order(static_cast<std::size_t>(samples.rows()));
  std::iota(order.begin(), order.end(), std::int64_t{0});
  RowMatrixXd prototypes(units, samples.cols());
  for (std::int32_t u = 0; u < units; ++u) {
    const std::int64_t pick = u + random.uniform_index(samples.rows() - u);
    std::swap(order[static_cast<std::size_t>(u)], order[static_cast<std::size_t>(pick)]);
    prototypes.row(u) = samples.row(order[static_cast<std::size_t>(u)]);
  }
  return prototypes;
}

// Gaussian neighbourhood on the grid is separable, h(k, u) = h_r(dr) h_c(dc), so the
// neighbourhood sums  sum_u h(k, u) [S_u, n_u]  are a 1-D smoothing along the
// columns and then along the rows: O(units (rows + cols) d) instead of O(units^2 d).
// Each output entry is a sum in a fixed order.
RowMatrixXd smooth_over_grid(const RowMatrixXd& sums, std::int32_t rows, std::int32_t cols,
                             double radius) {
  const double scale = 1.0 / (2.0 * radius * radius);
  auto weights = [&](std::int32_t count) {
    std::vector<double> h(static_cast<std::size_t>(count));
    for (std::int32_t k = 0; k < count; ++k)
      h[static_cast<std::size_t>(k)] = std::exp(-k * k * scale);
    return h;
  };
  const std::vector<double> h_col = weights(cols);
  const std::vector<double> h_row = weights(rows);
  const Eigen::Index width = sums.cols();
  RowMatrixXd along_cols = RowMatrixXd::Zero(sums.rows(), width);
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      auto out = along_cols.row(static_cast<Eigen::Index>(r) * cols + c);
      for (std::int32_t c2 = 0; c2 < cols; ++c2) {
        out += h_col[static_cast<std::size_t>(std::abs(c - c2))] *
               sums.row(static_cast<Eigen::Index>(r) * cols + c2);
      }
    }
  }
  RowMatrixXd smoothed = RowMatrixXd::Zero(sums.rows(), width);
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      auto out = smoothed.row(static_cast<Eigen::Index>(r) * cols + c);
      for (std::int32_t r2 = 0; r2 < rows; ++r2) {
        out += h_row[static_cast<std::size_t>(std::abs(r - r2))] *
               along_cols.row(static_cast<Eigen::Index>(r2) * cols + c);
      }
    }
  }
  return smoothed;
}

double mean_distance(std::span<const double> squared) {
  double sum = 0.0;
  for (double s : squared) sum += std::sqrt(s);  // in sample order: deterministic
  return sum / static_cast<double>(squared.size());
}

}  // namespace

double som_aspect_ratio(const Eigen::Ref<const RowMatrixXd>& samples, std::int64_t units) {
  validate_samples("som_aspect_ratio", samples);
  const PrincipalAxes axes = principal_axes(samples);
  const double first = axes.variance[0];
  const double second = axes.variance[1];
  // SOM Toolbox (som_topol_struct): nearly 1-D data gets a near-square map.
  if (!(second > 0.0) || second * static_cast<double>(units) < first) return 1.0;
  return std::max(1.0, std::sqrt(first / second));
}

SomGrid som_grid_for(std::int64_t num_samples, double aspect_ratio) {
  if (num_samples < 1) {
    throw std::invalid_argument("som_grid_for: need at least one sample, got " +
                                std::to_string(num_samples));
  }
  if (!(aspect_ratio >= 1.0) || !std::isfinite(aspect_ratio)) {
    throw std::invalid_argument("som_grid_for: aspect ratio must be finite and >= 1, got " +
                                std::to_string(aspect_ratio));
  }
  const std::int64_t units = unit_count_for(num_samples);
  std::int64_t rows =
      std::max<std::int64_t>(1, std::llround(std::sqrt(static_cast<double>(units) / aspect_ratio)));
  std::int64_t cols = std::max<std::int64_t>(
      1, std::llround(static_cast<double>(units) / static_cast<double>(rows)));
  if (rows * cols > num_samples) cols = num_samples / rows;  // rounding up past n
  if (rows > cols) std::swap(rows, cols);
  return {static_cast<std::int32_t>(rows), static_cast<std::int32_t>(cols)};
}

SomGrid som_grid_for(const Eigen::Ref<const RowMatrixXd>& samples) {
  validate_samples("som_grid_for", samples);
  return som_grid_for(samples.rows(), som_aspect_ratio(samples, unit_count_for(samples.rows())));
}

SelfOrganizingMap::SelfOrganizingMap(std::int32_t rows, std::int32_t cols, RowMatrixXd prototypes,
                                     std::vector<double> quantization_errors,
                                     std::vector<double> radii)
    : rows_(rows),
      cols_(cols),
      prototypes_(std::move(prototypes)),
      quantization_errors_(std::move(quantization_errors)),
      radii_(std::move(radii)) {
  check_grid("SelfOrganizingMap", rows, cols);
  if (prototypes_.rows() != static_cast<Eigen::Index>(rows) * cols || prototypes_.cols() < 1) {
    throw std::invalid_argument(
        "SelfOrganizingMap: prototypes are " + std::to_string(prototypes_.rows()) + " x " +
        std::to_string(prototypes_.cols()) + ", grid " + std::to_string(rows) + " x " +
        std::to_string(cols) + " needs one row of dimension >= 1 per unit");
  }
  if (!prototypes_.allFinite()) {
    throw std::invalid_argument("SelfOrganizingMap: prototypes contain NaN or infinity");
  }
  prototypes_by_dimension_ = dimension_major_table(prototypes_);
}

RowMatrixXd SelfOrganizingMap::grid_coordinates() const {
  RowMatrixXd coordinates(num_units(), 2);
  for (std::int32_t u = 0; u < num_units(); ++u) {
    coordinates(u, 0) = unit_row(u);
    coordinates(u, 1) = unit_col(u);
  }
  return coordinates;
}

BestMatch SelfOrganizingMap::best_matching_unit(std::span<const double> x) const {
  if (static_cast<Eigen::Index>(x.size()) != prototypes_.cols()) {
    throw std::invalid_argument("best_matching_unit: query has " + std::to_string(x.size()) +
                                " entries, the map's dimension is " +
                                std::to_string(prototypes_.cols()));
  }
  if (!std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); })) {
    throw std::invalid_argument("best_matching_unit: query contains NaN or infinity");
  }
  const SquaredMatch match =
#if GGK_AVX2_DISPATCH
      cpu_has_avx2()
          ? best_match_squared_avx2(x.data(), prototypes_by_dimension_, num_units(), dimension())
          :
#endif
          best_match_squared(x.data(), prototypes_by_dimension_, num_units(), dimension());
  return {match.unit, std::sqrt(match.squared_distance)};
}

BestMatches SelfOrganizingMap::best_matching_units(
    const Eigen::Ref<const RowMatrixXd>& queries) const {
  if (queries.cols() != prototypes_.cols()) {
    throw std::invalid_argument("best_matching_units: queries have dimension " +
                                std::to_string(queries.cols()) + ", the map's dimension is " +
                                std::to_string(prototypes_.cols()));
  }
  if (!queries.allFinite()) {
    throw std::invalid_argument("best_matching_units: queries contain NaN or infinity");
  }
  BestMatches result;
  result.units.resize(static_cast<std::size_t>(queries.rows()));
  result.distances.resize(static_cast<std::size_t>(queries.rows()));
  best_matches_squared(queries, prototypes_by_dimension_, num_units(), result.units,
                       result.distances);
  for (double& d : result.distances) d = std::sqrt(d);
  return result;
}

SelfOrganizingMap train_self_organizing_map(const Eigen::Ref<const RowMatrixXd>& samples,
                                            const SomOptions& options, RandomStream* random) {
  check_grid("train_self_organizing_map", options.rows, options.cols);
  validate_samples("train_self_organizing_map", samples);
  const std::int32_t units = options.rows * options.cols;
  if (units > samples.rows()) {
    throw std::invalid_argument("train_self_organizing_map: " + std::to_string(units) + " units (" +
                                std::to_string(options.rows) + " x " +
                                std::to_string(options.cols) + ") but only " +
                                std::to_string(samples.rows()) + " samples");
  }
  if (options.epochs < 1) {
    throw std::invalid_argument("train_self_organizing_map: epochs must be >= 1, got " +
                                std::to_string(options.epochs));
  }
  const double initial_radius = options.initial_radius.value_or(
      std::max(0.5 * std::max(options.rows, options.cols), options.final_radius));
  if (!(options.final_radius > 0.0) || !std::isfinite(initial_radius) ||
      !(initial_radius >= options.final_radius)) {
    throw std::invalid_argument("train_self_organizing_map: radii must satisfy 0 < final (" +
                                std::to_string(options.final_radius) + ") <= initial (" +
                                std::to_string(initial_radius) + ") < inf");
  }
  if (options.initialization == SomInitialization::random_samples && random == nullptr) {
    throw std::invalid_argument(
        "train_self_organizing_map: random_samples initialisation needs a RandomStream");
  }

  RowMatrixXd prototypes = options.initialization == SomInitialization::principal_components
                               ? principal_component_prototypes(samples, options.rows, options.cols)
                               : random_sample_prototypes(samples, units, *random);
  const std::vector<double> radii = radius_schedule(options, initial_radius);
  std::vector<double> quantization_errors;
  quantization_errors.reserve(radii.size());

  const auto n = static_cast<std::size_t>(samples.rows());
  const Eigen::Index dim = samples.cols();
  std::vector<std::int32_t> bmu(n);
  std::vector<double> squared(n);
  std::vector<double> table = dimension_major_table(prototypes);
  best_matches_squared(samples, table, units, bmu, squared);
  // Per-unit sums S_u in columns [0, d) and counts n_u in column d.
  RowMatrixXd sums(units, dim + 1);
  for (const double radius : radii) {
    sums.setZero();
    for (std::size_t i = 0; i < n; ++i) {  // sample order: deterministic
      auto row = sums.row(bmu[i]);
      row.head(dim) += samples.row(static_cast<Eigen::Index>(i));
      row(dim) += 1.0;
    }
    const RowMatrixXd smoothed = smooth_over_grid(sums, options.rows, options.cols, radius);
    for (std::int32_t k = 0; k < units; ++k) {
      const double mass = smoothed(k, dim);
      // Zero (or subnormal, i.e. underflowed) mass: no sample near; keep the prototype.
      if (std::isnormal(mass)) prototypes.row(k) = smoothed.row(k).head(dim) / mass;
    }
    table = dimension_major_table(prototypes);
    best_matches_squared(samples, table, units, bmu, squared);
    quantization_errors.push_back(mean_distance(squared));
  }
  return SelfOrganizingMap(options.rows, options.cols, std::move(prototypes),
                           std::move(quantization_errors), radii);
}

}  // namespace ggk::kernels
