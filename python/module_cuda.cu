// The CUDA kernels of a scene's Python module (README, "PyTorch"), built by
// sweepgen_add_python_module() where the module's solver has its CUDA library
// (cmake/SweepgenAddPythonModule.cmake): nvcc compiles the generated .cu (SWEEPGEN_MODULE_CUDA_SOURCE:
// its kernels, launchers and, for the host, a copy of the solver's functions) into a shared library
// of its own, every symbol hidden but the one function below, which hands the module the launchers
// by policy (python/module_api.hpp, CudaTables). The module calls them on tensors' device memory
// (the binding's _solve_cuda and _derivatives_cuda).
#include <cuda_runtime.h>

#include <cstddef>
#include <iterator>
#include <utility>

#include SWEEPGEN_MODULE_CUDA_SOURCE
#include "module_api.hpp"
#include "sweepgen_module_scene.hpp"

namespace scene = SWEEPGEN_MODULE_SCENE;

namespace {

// Entry k of a generated table of launchers (cuda_solves, derivative_cuda_solves: Table::entries)
// behind the module's untyped signature: the stream as void*, the CUDA error as its text.
template <class Table, std::size_t k>
const char* launch(int n, const typename Table::Scalar* in, typename Table::Scalar* out, void* stream) {
  const cudaError_t status = Table::entries[k].solve(n, in, out, static_cast<cudaStream_t>(stream));
  return status == cudaSuccess ? nullptr : cudaGetErrorString(status);
}

template <class Table, std::size_t... k>
void fill(const typename sweepgen_python::Variant<typename Table::Scalar>::CudaSolve*& entries, int& count,
          std::index_sequence<k...>) {
  static const typename sweepgen_python::Variant<typename Table::Scalar>::CudaSolve table[] = {
      {Table::entries[k].policy, &launch<Table, k>}...};
  entries = table;
  count = static_cast<int>(sizeof...(k));
}

template <class Table>
void fill(const typename sweepgen_python::Variant<typename Table::Scalar>::CudaSolve*& entries, int& count) {
  fill<Table>(entries, count, std::make_index_sequence<std::size(Table::entries)>{});
}

#define SWEEPGEN_MODULE_CUDA_TABLE(Name, tag, table) \
  struct Name {                                      \
    using Scalar = scene::tag::Scalar;               \
    static constexpr const auto& entries = scene::tag::table; \
  };
#if SWEEPGEN_MODULE_HAS_F64
SWEEPGEN_MODULE_CUDA_TABLE(F64Solves, f64, cuda_solves)
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
SWEEPGEN_MODULE_CUDA_TABLE(F64Derivatives, f64, derivative_cuda_solves)
#endif
#endif
#if SWEEPGEN_MODULE_HAS_F32
SWEEPGEN_MODULE_CUDA_TABLE(F32Solves, f32, cuda_solves)
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
SWEEPGEN_MODULE_CUDA_TABLE(F32Derivatives, f32, derivative_cuda_solves)
#endif
#endif
#undef SWEEPGEN_MODULE_CUDA_TABLE

}  // namespace

extern "C" __attribute__((visibility("default"))) void SWEEPGEN_MODULE_CUDA_TABLES(SWEEPGEN_MODULE_NAME)(
    sweepgen_python::CudaTables* tables) {
#if SWEEPGEN_MODULE_HAS_F64
  fill<F64Solves>(tables->f64.solves, tables->f64.solve_count);
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
  fill<F64Derivatives>(tables->f64.derivative_solves, tables->f64.derivative_count);
#endif
#endif
#if SWEEPGEN_MODULE_HAS_F32
  fill<F32Solves>(tables->f32.solves, tables->f32.solve_count);
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
  fill<F32Derivatives>(tables->f32.derivative_solves, tables->f32.derivative_count);
#endif
#endif
}
