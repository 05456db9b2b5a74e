#include "engine/run/fit_warnings.hpp"

namespace ggk::engine {

void FitWarnings::add(const RunRecord& record) {
  const std::lock_guard<std::mutex> lock(mutex_);
  for (const FitRecord& fit : record.fits) {
    Kind& kind = kinds_[{std::string(kernel_type_name(fit.point.basis)), fit.point.kernels}];
    ++kind.fits;
    if (fit.warning.empty()) continue;
    ++kind.warned;
    const auto at = std::tuple{record.configuration, record.run, fit.point.index};
    if (at < kind.first) {
      kind.first = at;
      kind.text = fit.warning;
    }
  }
}

std::vector<std::string> FitWarnings::lines() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> lines;
  for (const auto& [key, kind] : kinds_) {
    if (kind.warned == 0) continue;
    lines.push_back(key.first + ", " + std::to_string(key.second) +
                    " kernels: " + std::to_string(kind.warned) + " of " +
                    std::to_string(kind.fits) + " fits (attribute warning), e.g. run " +
                    std::to_string(std::get<1>(kind.first)) + ": " + kind.text);
  }
  return lines;
}

}  // namespace ggk::engine
