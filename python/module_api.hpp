// What a scene's Python module (python/module.cpp, compiled per scene, without pybind11) hands the
// binding (python/binding.cpp, compiled once per build and linked into every module): the scene's
// sizes, its generated entry points behind untyped pointers, and where each result lies in the
// generated structs. Why two files: pybind11's templates cost a module ~11 s of g++; compiled once,
// a module compiles in well under a second (bench/README.md, "Build and CI time").
#pragma once

#include <Python.h>

#include <cstddef>
#include <vector>

namespace sweepgen_python {

// A member of a generated struct: its offset in bytes and its number of values (0: the struct has
// no such member).
struct Member {
  std::size_t offset = 0;
  int width = 0;
};

// One scalar variant of the generated code (namespace f64 or f32).
template <class Scalar>
struct Variant {
  const char* name = "";  // "f64" or "f32"
  int flat_in_size = 0, flat_out_size = 0;
  std::size_t state_size = 0, solution_size = 0;  // sizeof(State), sizeof(Solution)
  void (*outward)(const Scalar* q, const Scalar* qd, void* state) = nullptr;
  void (*decompose)(const Scalar* flat_drivers, void* state) = nullptr;
  struct Solve {
    const char* policy;
    void (*solve)(const void* state, const Scalar* beta, void* solution);
  };
  struct Flat {
    const char* policy;
    void (*solve)(const Scalar* in, Scalar* out);
  };
  struct Batch {
    const char* policy;
    void (*solve)(int n, const Scalar* in, Scalar* out);
  };
  std::vector<Solve> solves;  // the generated tables: solves, flat_solves, batch_solves
  std::vector<Flat> flat_solves;
  std::vector<Batch> batch_solves;
  // Solution's members.
  Member qdd, tau_cmd, tau_ctrl, nu, tip_acceleration, set_acceleration, closure_error, coupling_torque, saturated;
  std::size_t dropped_pivots = 0, locked_joints = 0, status = 0;  // offsets of an int, an int, an unsigned

  // The derivative functions (scene key derivatives; none: derivative_solves empty).
  struct DerivativeSolve {
    const char* policy;
    void (*solve)(const Scalar* q, const Scalar* qd, const Scalar* flat_drivers, const Scalar* beta, void* derivatives);
  };
  std::vector<DerivativeSolve> derivative_solves;
  std::vector<Batch> derivative_batch_solves;
  std::size_t derivatives_size = 0;  // sizeof(Derivatives)
  int derivative_columns = 0, derivative_flat_out_size = 0;
  // Derivatives' members: the values, their Jacobians (width 0 where not returned), the status.
  Member d_values[3], d_jacobians[3];  // qdd, nu, tau_cmd
  std::size_t d_status = 0;

  // The CUDA kernels (python/module_cuda.cu; none: the module is built without CUDA): n states in
  // device memory in the batch layout, launched on `stream` (a cudaStream_t); the CUDA error's
  // text, or null once queued.
  struct CudaSolve {
    const char* policy;
    const char* (*solve)(int n, const Scalar* in, Scalar* out, void* stream);
  };
  std::vector<CudaSolve> cuda_solves, derivative_cuda_solves;
};

// What a module's CUDA library (python/module_cuda.cu, compiled by nvcc into a shared library of
// its own) hands the module: its kernels' launchers by policy, per scalar (null where the scene
// lacks the scalar). A shared library, so that the nvcc-compiled copy of the generated host
// functions stays hidden in it beside the module's own (the static solver library's, with the
// batch entry points that nvcc does not compile).
template <class Scalar>
struct CudaTable {
  const typename Variant<Scalar>::CudaSolve* solves = nullptr;
  int solve_count = 0;
  const typename Variant<Scalar>::CudaSolve* derivative_solves = nullptr;
  int derivative_count = 0;
};
struct CudaTables {
  CudaTable<double> f64;
  CudaTable<float> f32;
};
// The module's CUDA library's one exported function, named after the module (two modules' libraries
// in one process do not meet): fills a CudaTables.
#define SWEEPGEN_MODULE_CUDA_TABLES(name) SWEEPGEN_MODULE_CUDA_TABLES_(name)
#define SWEEPGEN_MODULE_CUDA_TABLES_(name) sweepgen_cuda_tables_##name

struct Scene {
  const char* module_name = "";  // SWEEPGEN_MODULE_NAME
  const char* scene_name = "";   // the scene's C++ namespace
  const char* flat_in_layout = "";
  const char* flat_out_layout = "";
  const char* torch_layer = "";  // python/torch_layer.py's text
  int dof = 0, nq = 0, nv = 0, constraints = 0;
  bool checks_inputs = false;
  unsigned status_ok = 0, status_constraint_rank_deficient = 0, status_saturated = 0, status_not_finite = 0,
           status_joint_inertia_singular = 0;
  const Variant<double>* f64 = nullptr;  // null where the scene lacks the scalar
  const Variant<float>* f32 = nullptr;
};

// The module `scene.module_name` (PyInit_<name>'s result): a new reference, or null with the
// Python error set.
PyObject* make_module(const Scene& scene) noexcept;

}  // namespace sweepgen_python
