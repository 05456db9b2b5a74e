// ggk.confidence_sequence and ggk.asymptotic_confidence_sequence: the anytime-valid confidence
// sequence of an adaptive study's paired differences (kernels/confidence_sequence.hpp), the C++
// twin of ggk_results.confidence_sequence.
#include "kernels/confidence_sequence.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"

namespace ggk::python {

void bind_sequential(py::module_& module) {
  module.def(
      "confidence_sequence",
      [](const DoubleArray& differences, double low, double high, double level) {
        kernels::ConfidenceSequence cs =
            kernels::confidence_sequence(double_span(differences, "differences"), low, high, level);
        return py::make_tuple(to_numpy(std::move(cs.lower)), to_numpy(std::move(cs.upper)));
      },
      py::arg("differences"), py::arg("low"), py::arg("high"), py::arg("level") = 0.95,
      R"((lower, upper) after each prefix of the differences (run order), each in
[low, high]: Waudby-Smith & Ramdas's predictable plug-in empirical-Bernstein
confidence sequence, valid at every look at once (optional stopping).)");
  module.def(
      "asymptotic_confidence_sequence",
      [](const DoubleArray& differences, double level, std::int64_t horizon) {
        kernels::ConfidenceSequence cs = kernels::asymptotic_confidence_sequence(
            double_span(differences, "differences"), level, horizon);
        return py::make_tuple(to_numpy(std::move(cs.lower)), to_numpy(std::move(cs.upper)));
      },
      py::arg("differences"), py::arg("level") = 0.95, py::arg("horizon") = 20,
      R"((lower, upper) after each prefix of the differences (run order): the
asymptotic confidence sequence of Waudby-Smith, Arnold, Wu, Chang & Ramdas
(2024), tightest at t = horizon, with Student's small-sample factor; no range
needed, valid as the runs grow.)");
}

}  // namespace ggk::python
