#include "engine/job/job_spec.hpp"

namespace ggk::engine {

std::string_view kernel_type_name(KernelType type) {
  switch (type) {
    case KernelType::ggk:
      return "ggk";
    case KernelType::ogk:
      return "ogk";
    case KernelType::pvf:
      return "pvf";
  }
  return "unknown";
}

std::string_view solver_name(kernels::LspiSolver solver) {
  switch (solver) {
    case kernels::LspiSolver::brm:
      return "brm";
    case kernels::LspiSolver::lstdq:
      return "lstdq";
  }
  return "unknown";
}

std::string_view basis_scheme_name(kernels::BasisScheme scheme) {
  switch (scheme) {
    case kernels::BasisScheme::shift:
      return "shift";
    case kernels::BasisScheme::copy:
      return "copy";
  }
  return "unknown";
}

}  // namespace ggk::engine
