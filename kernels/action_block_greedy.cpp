#include "kernels/action_block_greedy.hpp"

#include <stdexcept>
#include <string>

#include "kernels/first_best.hpp"

namespace ggk::kernels {

namespace {

// Q of one row as Eigen's sparse-dense product sums it.
double row_value(const SparseRowMatrix& features, Eigen::Index row, const double* weights) {
  double sum = 0.0;
  for (SparseRowMatrix::InnerIterator it(features, row); it; ++it) {
    sum += it.value() * weights[it.index()];
  }
  return sum;
}

// The greedy actions of every state for m = kActions actions (any m when kActions
// is 0: a runtime count, summed one row at a time).
template <std::int32_t kActions>
void greedy_states(const SparseRowMatrix& features, std::int32_t m, const double* weights,
                   std::vector<std::int32_t>& policy) {
  const Eigen::Index p = features.cols() / m;
  const auto* outer = features.outerIndexPtr();
  const auto* inner = features.innerIndexPtr();
  const double* values = features.valuePtr();
  std::vector<double> q(static_cast<std::size_t>(m));
  for (std::size_t s = 0; s < policy.size(); ++s) {
    const auto first = static_cast<Eigen::Index>(s) * m;
    bool dense = kActions > 0;
    for (std::int32_t a = 0; dense && a < m; ++a) {
      const auto begin = outer[first + a], end = outer[first + a + 1];
      dense = end - begin == p &&
              (p == 0 || (inner[begin] == a * p && inner[end - 1] == a * p + p - 1));
    }
    if constexpr (kActions > 0) {
      if (dense) {
        // The m rows are consecutive: row a's entry j at values[start + a p + j],
        // its weight at weights[a p + j].
        const double* v = values + outer[first];
        double sums[kActions] = {};
        for (Eigen::Index j = 0; j < p; ++j) {
          for (std::int32_t a = 0; a < kActions; ++a) sums[a] += v[a * p + j] * weights[a * p + j];
        }
        policy[s] = first_best(sums, kActions);
        continue;
      }
    }
    for (std::int32_t a = 0; a < m; ++a) {
      q[static_cast<std::size_t>(a)] = row_value(features, first + a, weights);
    }
    policy[s] = first_best(q.data(), m);
  }
}

}  // namespace

std::vector<std::int32_t> action_block_greedy(const SparseRowMatrix& features,
                                              std::int32_t num_actions,
                                              const Eigen::VectorXd& weights) {
  if (num_actions < 1 || features.rows() % num_actions != 0 || features.cols() % num_actions != 0 ||
      weights.size() != features.cols() || !features.isCompressed()) {
    throw std::invalid_argument("action_block_greedy: a " + std::to_string(features.rows()) +
                                " x " + std::to_string(features.cols()) + " table (" +
                                (features.isCompressed() ? "compressed" : "not compressed") +
                                "), " + std::to_string(num_actions) + " actions and " +
                                std::to_string(weights.size()) + " weights");
  }
  std::vector<std::int32_t> policy(static_cast<std::size_t>(features.rows() / num_actions), 0);
  switch (num_actions) {
    case 2:
      greedy_states<2>(features, num_actions, weights.data(), policy);
      break;
    case 3:
      greedy_states<3>(features, num_actions, weights.data(), policy);
      break;
    case 4:
      greedy_states<4>(features, num_actions, weights.data(), policy);
      break;
    default:
      greedy_states<0>(features, num_actions, weights.data(), policy);
      break;
  }
  return policy;
}

}  // namespace ggk::kernels
