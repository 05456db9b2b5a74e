#pragma once
// State-action basis functions built from state kernels (paper sec. 3, Eq. (9)).
//
// Input: state_kernels, N x p (row i = K(s_i, c_1..c_p)). Output: the feature
// table, (N m) x (m p) sparse row-major, whose row s * m + a is phi(s, a). Column
// a * p + j holds the kernel of centre j for action a; all other action blocks of a
// row are zero (the indicator I(a = a^(i)) of Eq. (9)).

#include <cstdint>

#include "kernels/eigen_types.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::kernels {

enum class BasisScheme { copy, shift };

// Copy scheme: phi_{a,j}(s, a) = K(s, c_j).
SparseRowMatrix copy_basis(const SparseRowMatrix& state_kernels, std::int32_t num_actions);

// Shift scheme, Eq. (9): phi_{a,j}(s, a) = sum_s' P(s'|s,a) K(s', c_j), with P the
// empirical model; an (s, a) never observed falls back to the copy scheme.
// model.num_states() must equal state_kernels.rows().
SparseRowMatrix shift_basis(const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                            const EmpiricalTransitionModel& model);

}  // namespace ggk::kernels
