#pragma once
// Gaussian kernels on states (paper sec. 3).
//
// Each function returns an N x p sparse row-major matrix of kernel values
// K(s_i, c_j). Values below `truncation` become structural zeros so that feature
// rows stay sparse; truncation = 0 keeps every non-zero value. An infinite
// shortest-path distance (unreachable node) gives 0. A NaN distance, an infinite
// Euclidean distance or a non-finite observation, centre or distance to the nearest
// node is refused (NonFiniteKernelValue naming the state and the centre): it would
// otherwise drop out of the table as a zero, a wrong but plausible-looking feature.

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// A kernel value that cannot be formed from finite numbers: state() is the row
// (the state's index in the call's input), centre() the column (-1: every centre,
// the state's own input is not finite).
class NonFiniteKernelValue : public std::domain_error {
 public:
  NonFiniteKernelValue(const std::string& what, Eigen::Index state, Eigen::Index centre)
      : std::domain_error(what), state_(state), centre_(centre) {}
  Eigen::Index state() const { return state_; }
  Eigen::Index centre() const { return centre_; }

 private:
  Eigen::Index state_;
  Eigen::Index centre_;
};

// exp(-d^2 / (2 sigma^2)); sigma > 0.
double gaussian(double distance, double sigma);

// Ordinary Gaussian kernels, Eq. (7): ED(s, c) is the Euclidean distance between
// states.row(i) and centers.row(j).
SparseRowMatrix ordinary_gaussian_kernels(const Eigen::Ref<const RowMatrixXd>& states,
                                          const Eigen::Ref<const RowMatrixXd>& centers,
                                          double sigma, double truncation = 0.0);

// Geodesic Gaussian kernels, Eq. (8), on graph nodes: center_distances is p x N
// (row j = shortest-path distances from centre j, as geodesic_distances returns).
SparseRowMatrix geodesic_gaussian_kernels(const Eigen::Ref<const RowMatrixXd>& center_distances,
                                          double sigma, double truncation = 0.0);

// Continuous geodesic Gaussian kernels for states off the graph (paper sec. 4.2):
// SP(s, c) = ED(s, n(s)) + SP(n(s), c), where n(s) = nearest_node[i] is the state's
// nearest graph node and distance_to_nearest[i] = ED(s, n(s)).
SparseRowMatrix continuous_geodesic_gaussian_kernels(
    std::span<const std::int32_t> nearest_node, std::span<const double> distance_to_nearest,
    const Eigen::Ref<const RowMatrixXd>& center_distances, double sigma, double truncation = 0.0);

// The kernels of the first p centres from those of more: every entry depends on
// its state and centre alone, so the leading p columns of a table built for
// centres c_0 .. c_{q-1} (q >= p, compressed) are bit for bit the table each
// function above builds for c_0 .. c_{p-1}, truncation included. A sweep over
// kernel counts builds the largest count's table once and takes the others from
// it (the Khepera's OGK: 550 columns of exp per run instead of 100 ... 10, summed).
// std::invalid_argument when p exceeds the columns or the table is not compressed.
SparseRowMatrix leading_columns(const SparseRowMatrix& kernels, Eigen::Index p);

}  // namespace ggk::kernels
