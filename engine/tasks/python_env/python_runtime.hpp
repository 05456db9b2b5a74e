#pragma once
// The CPython that ggk embeds for the python_env task (pybind11's embedding,
// Debian's python3-dev): started once per process on first use, without
// Python's signal handlers (ggk owns SIGINT and SIGTERM), and its GIL released
// at once, so that any thread may take it for its calls into an environment
// (pybind11::gil_scoped_acquire). Never finalised: a run's threads may hold
// environment objects until the process exits, and CPython's finalisation under
// live threads is what its documentation warns against.
//
// Only engine/tasks/python_env/ includes pybind11; this header does not.

#include <string>

namespace ggk::engine::python {

// Starts the interpreter if it is not running (thread-safe).
void ensure_interpreter();

// "CPython 3.11.2" of the library ggk was linked with (without starting it).
std::string embedded_version();

}  // namespace ggk::engine::python
