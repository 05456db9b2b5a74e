#include "engine/tasks/python_env/python_runtime.hpp"

#include <mutex>

#include <pybind11/embed.h>

namespace ggk::engine::python {

void ensure_interpreter() {
  static std::once_flag started;
  std::call_once(started, [] {
    pybind11::initialize_interpreter(/*init_signal_handlers=*/false);
    PyEval_SaveThread();  // the GIL released: taken per call by the thread that calls
  });
}

std::string embedded_version() {
  return std::string("CPython ") + PY_VERSION;
}

}  // namespace ggk::engine::python
