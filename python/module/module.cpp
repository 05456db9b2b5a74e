// The Python module `ggk` (python/module/README.md): the engine's numerics for
// notebooks and scripts, each function the kernels/ function the engine's fits
// call, so a fit here equals the engine's fit of the same samples bit for bit.
#include <pybind11/pybind11.h>

#include "kernels/blas_runtime.hpp"
#include "python/module/bindings.hpp"

#ifndef GGK_VERSION_STRING
#define GGK_VERSION_STRING "0.1.0"
#endif

PYBIND11_MODULE(ggk, module) {
  module.doc() = R"(ggk: geodesic Gaussian kernels, proto-value functions and LSPI.

graph:    transition_graph, graph_from_edges, Graph, shortest_paths
kernels:  ordinary_kernels, geodesic_kernels, continuous_geodesic_kernels,
          nearest_visited_states
PVF:      graph_laplacian, proto_value_functions
bases:    copy_basis, shift_basis, table_basis, Basis
SOM:      train_som, som_grid, SelfOrganizingMap
LSPI:     Samples, lspi, LspiFit
Gymnasium-API environments: random_walks, greedy_episodes, RandomWalks
adaptive studies: confidence_sequence

Arrays in: numpy (C-contiguous float64 / int32 read in place), scipy.sparse for
tables; out: numpy arrays and scipy.sparse.csr_matrix over the engine's own
buffers. Errors are ValueError / RuntimeError with the engine's messages; the GIL
is released while the numerics run. The BLAS runs one thread per call (the
engine's rule, kernels/blas_runtime.hpp), for numpy too when numpy shares it.)";
  module.attr("__version__") = GGK_VERSION_STRING;
  module.def(
      "blas", [] { return ggk::kernels::blas_info().name; },
      "The BLAS and LAPACK the numerics call (their bits depend on it).");
  ggk::python::bind_graphs(module);
  ggk::python::bind_kernel_tables(module);
  ggk::python::bind_proto_value_functions(module);
  ggk::python::bind_bases(module);
  ggk::python::bind_som(module);
  ggk::python::bind_lspi(module);
  ggk::python::bind_environments(module);
  ggk::python::bind_sequential(module);
}
