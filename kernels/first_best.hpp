#pragma once
// The greedy action of Q values q[0 .. m): the first largest, ties to the lowest
// action (greedy_policy's rule, lspi.hpp), shared by the greedy steps that compute
// Q their own way (copy_basis_greedy, action_block_greedy).

#include <cstdint>

namespace ggk::kernels {

inline std::int32_t first_best(const double* q, std::int32_t m) {
  std::int32_t best = 0;
  for (std::int32_t a = 1; a < m; ++a) {
    if (q[a] > q[best]) best = a;
  }
  return best;
}

}  // namespace ggk::kernels
