#pragma once
// ggk.Basis: a state-action basis as LSPI reads it (paper Eq. (9)).
//
// A copy basis keeps only its N x p state kernels (the (N m) x (m p) table is never
// formed: fit_lspi_copy_basis reads the kernels, the same fit bit for bit); a shift
// basis or a table the caller built keeps the table.
#include <cstdint>
#include <string>

#include "kernels/eigen_types.hpp"

namespace ggk::python {

struct StateActionBasis {
  std::string scheme;  // "copy", "shift" or "table"
  std::int32_t num_actions = 0;
  kernels::SparseRowMatrix state_kernels;  // copy: N x p
  kernels::SparseRowMatrix table;          // shift, table: (N m) x k

  std::int64_t num_states() const;
  std::int64_t num_features() const;
  bool is_copy() const { return scheme == "copy"; }
};

}  // namespace ggk::python
