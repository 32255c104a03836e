// The Python module of one generated scene solver (README, "Python"), built by
// sweepgen_add_python_module() (cmake/SweepgenAddPythonModule.cmake). One source for every scene:
// it describes the scene to the binding (python/module_api.hpp; python/binding.cpp, compiled once
// per build, binds it), the module name from SWEEPGEN_MODULE_NAME, everything else from the
// generated header through sweepgen_module_scene.hpp, which the CMake function writes per module:
//   SWEEPGEN_MODULE_SCENE      the scene's C++ namespace (the scene's `solver:` entry)
//   SWEEPGEN_MODULE_HAS_F64/32 whether the header has namespace f64 / f32 (the scene's `scalars:`)
//   SWEEPGEN_MODULE_FLAT_IN/OUT the flat layout as the header's comment states it
//   SWEEPGEN_MODULE_HAS_DERIVATIVES whether the header has the derivative functions (scene key derivatives)
//   sweepgen_module_torch_layer python/torch_layer.py's text (`<module>.torch`)
// and, from the CMake function, SWEEPGEN_MODULE_HAS_CUDA where the module is built with its
// solver's CUDA kernels (python/module_cuda.cu, a shared library beside the module).
#include <cstddef>
#include <iterator>
#include <type_traits>
#include <utility>

#include "module_api.hpp"
#include "sweepgen_module_scene.hpp"

namespace scene = SWEEPGEN_MODULE_SCENE;

#if SWEEPGEN_MODULE_HAS_CUDA
// python/module_cuda.cu's one exported function.
extern "C" void SWEEPGEN_MODULE_CUDA_TABLES(SWEEPGEN_MODULE_NAME)(sweepgen_python::CudaTables* tables);
#endif

namespace {

using sweepgen_python::Member;

static_assert(scene::returns_every_output,
              "the Python module binds every result of a solve: leave the scene key 'outputs' out, or list them all");

// Where a member of a generated struct lies, and its number of values; Member{} where the struct has
// none (nu without constraints, set_acceleration without listed sets, closure_error without sets
// between two links, coupling_torque without coupled joints, a Jacobian the scene does not ask for).
#define SWEEPGEN_MODULE_MEMBER(member)                                                                  \
  template <class Struct, class = void>                                                                 \
  struct member##_of {                                                                                  \
    static constexpr Member value{};                                                                    \
  };                                                                                                    \
  template <class Struct>                                                                               \
  struct member##_of<Struct, std::void_t<decltype(&Struct::member)>> {                                  \
    static constexpr Member value{offsetof(Struct, member),                                             \
                                  static_cast<int>(std::extent_v<decltype(Struct::member)>)};           \
  };
SWEEPGEN_MODULE_MEMBER(qdd)
SWEEPGEN_MODULE_MEMBER(tau_cmd)
SWEEPGEN_MODULE_MEMBER(tau_ctrl)
SWEEPGEN_MODULE_MEMBER(nu)
SWEEPGEN_MODULE_MEMBER(tip_acceleration)
SWEEPGEN_MODULE_MEMBER(set_acceleration)
SWEEPGEN_MODULE_MEMBER(closure_error)
SWEEPGEN_MODULE_MEMBER(coupling_torque)
SWEEPGEN_MODULE_MEMBER(saturated)
SWEEPGEN_MODULE_MEMBER(d_qdd)
SWEEPGEN_MODULE_MEMBER(d_nu)
SWEEPGEN_MODULE_MEMBER(d_tau_cmd)
#undef SWEEPGEN_MODULE_MEMBER

// A variant's entry points behind the binding's untyped pointers. V: the generated namespace's
// types and tables (a struct of the macro below).
template <class V>
struct Entries {
  using Scalar = typename V::Scalar;
  static void outward(const Scalar* q, const Scalar* qd, void* state) {
    V::outward(q, qd, *static_cast<typename V::State*>(state));
  }
  static void decompose(const Scalar* flat_drivers, void* state) {
    V::decompose(V::drivers_from_flat(flat_drivers), *static_cast<typename V::State*>(state));
  }
  template <std::size_t k>
  static void solve(const void* state, const Scalar* beta, void* solution) {
    V::solves[k].solve(*static_cast<const typename V::State*>(state), beta, *static_cast<typename V::Solution*>(solution));
  }
  template <std::size_t... k>
  static auto solves(std::index_sequence<k...>) {
    return std::vector<typename sweepgen_python::Variant<Scalar>::Solve>{{V::solves[k].policy, &solve<k>}...};
  }
};

template <class V>
sweepgen_python::Variant<typename V::Scalar> variant_of() {
  using Scalar = typename V::Scalar;
  using Solution = typename V::Solution;
  sweepgen_python::Variant<Scalar> v;
  v.name = V::name;
  v.flat_in_size = V::flat_in_size;
  v.flat_out_size = V::flat_out_size;
  v.state_size = sizeof(typename V::State);
  v.solution_size = sizeof(Solution);
  v.outward = &Entries<V>::outward;
  v.decompose = &Entries<V>::decompose;
  v.solves = Entries<V>::solves(std::make_index_sequence<std::size(V::solves)>{});
  for (const auto& entry : V::flat_solves) v.flat_solves.push_back({entry.policy, entry.solve});
  for (const auto& entry : V::batch_solves) v.batch_solves.push_back({entry.policy, entry.solve});
  v.qdd = qdd_of<Solution>::value;
  v.tau_cmd = tau_cmd_of<Solution>::value;
  v.tau_ctrl = tau_ctrl_of<Solution>::value;
  v.nu = nu_of<Solution>::value;
  v.tip_acceleration = tip_acceleration_of<Solution>::value;
  v.set_acceleration = set_acceleration_of<Solution>::value;
  v.closure_error = closure_error_of<Solution>::value;
  v.coupling_torque = coupling_torque_of<Solution>::value;
  v.saturated = saturated_of<Solution>::value;
  v.dropped_pivots = offsetof(Solution, dropped_pivots);
  v.locked_joints = offsetof(Solution, locked_joints);
  v.status = offsetof(Solution, status);
  return v;
}

#if SWEEPGEN_MODULE_HAS_DERIVATIVES
// The derivative functions of a variant (scene key derivatives), by policy.
template <class V>
struct DerivativeEntries {
  using Scalar = typename V::Scalar;
  template <std::size_t k>
  static void solve(const Scalar* q, const Scalar* qd, const Scalar* flat_drivers, const Scalar* beta, void* out) {
    V::derivative_solves[k].solve(q, qd, V::drivers_from_flat(flat_drivers), beta,
                                  *static_cast<typename V::Derivatives*>(out));
  }
  template <std::size_t... k>
  static auto solves(std::index_sequence<k...>) {
    return std::vector<typename sweepgen_python::Variant<Scalar>::DerivativeSolve>{
        {V::derivative_solves[k].policy, &solve<k>}...};
  }
};

template <class V>
void add_derivatives(sweepgen_python::Variant<typename V::Scalar>& v) {
  using Derivatives = typename V::Derivatives;
  v.derivative_solves = DerivativeEntries<V>::solves(std::make_index_sequence<std::size(V::derivative_solves)>{});
  for (const auto& entry : V::derivative_batch_solves) v.derivative_batch_solves.push_back({entry.policy, entry.solve});
  v.derivatives_size = sizeof(Derivatives);
  v.derivative_columns = V::derivative_columns;
  v.derivative_flat_out_size = V::derivative_flat_out_size;
  v.d_values[0] = qdd_of<Derivatives>::value;
  v.d_values[1] = nu_of<Derivatives>::value;
  v.d_values[2] = tau_cmd_of<Derivatives>::value;
  // The Jacobians the scene returns (the header's derivative_of_*: a member only where true).
  v.d_jacobians[0] = V::derivative_of_qdd ? d_qdd_of<Derivatives>::value : Member{};
  v.d_jacobians[1] = V::derivative_of_nu ? d_nu_of<Derivatives>::value : Member{};
  v.d_jacobians[2] = V::derivative_of_tau_cmd ? d_tau_cmd_of<Derivatives>::value : Member{};
  v.d_status = offsetof(Derivatives, status);
}
#endif

// One scalar variant of the generated code (namespace f64 or f32): types, tables, entry points.
#define SWEEPGEN_MODULE_VARIANT(Name, tag)                                                               \
  struct Name {                                                                                          \
    using Scalar = scene::tag::Scalar;                                                                   \
    using State = scene::tag::State;                                                                     \
    using Solution = scene::tag::Solution;                                                               \
    static constexpr const char* name = #tag;                                                            \
    static constexpr int flat_in_size = scene::tag::flat_in_size;                                        \
    static constexpr int flat_out_size = scene::tag::flat_out_size;                                      \
    static constexpr const auto& solves = scene::tag::solves;                                            \
    static constexpr const auto& flat_solves = scene::tag::flat_solves;                                  \
    static constexpr const auto& batch_solves = scene::tag::batch_solves;                                \
    static void outward(const Scalar* q, const Scalar* qd, State& s) { scene::tag::outward(q, qd, s); } \
    static void decompose(const scene::tag::Drivers& d, State& s) { scene::tag::decompose(d, s); }       \
    static auto drivers_from_flat(const Scalar* drivers) { return scene::tag::drivers_from_flat(drivers); } \
    SWEEPGEN_MODULE_VARIANT_DERIVATIVES(tag)                                                             \
  }
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
#define SWEEPGEN_MODULE_VARIANT_DERIVATIVES(tag)                                                         \
  using Derivatives = scene::tag::Derivatives;                                                           \
  static constexpr int derivative_columns = scene::tag::derivative_columns;                              \
  static constexpr bool derivative_of_qdd = scene::tag::derivative_of_qdd;                               \
  static constexpr bool derivative_of_nu = scene::tag::derivative_of_nu;                                 \
  static constexpr bool derivative_of_tau_cmd = scene::tag::derivative_of_tau_cmd;                       \
  static constexpr const auto& derivative_solves = scene::tag::derivative_solves;                        \
  static constexpr const auto& derivative_batch_solves = scene::tag::derivative_batch_solves;            \
  static constexpr int derivative_flat_out_size = scene::tag::derivative_flat_out_size;
#else
#define SWEEPGEN_MODULE_VARIANT_DERIVATIVES(tag)
#endif

#if SWEEPGEN_MODULE_HAS_CUDA
// The kernels of a variant (its scalar's table from the module's CUDA library).
template <class Scalar>
void add_cuda(sweepgen_python::Variant<Scalar>& v) {
  static const sweepgen_python::CudaTables tables = [] {
    sweepgen_python::CudaTables t;
    SWEEPGEN_MODULE_CUDA_TABLES(SWEEPGEN_MODULE_NAME)(&t);
    return t;
  }();
  const sweepgen_python::CudaTable<Scalar>& table = [&]() -> const sweepgen_python::CudaTable<Scalar>& {
    if constexpr (std::is_same_v<Scalar, double>) return tables.f64;
    else return tables.f32;
  }();
  v.cuda_solves.assign(table.solves, table.solves + table.solve_count);
  v.derivative_cuda_solves.assign(table.derivative_solves, table.derivative_solves + table.derivative_count);
}
#endif

template <class V>
const sweepgen_python::Variant<typename V::Scalar>* described() {
  static const sweepgen_python::Variant<typename V::Scalar> v = [] {
    auto variant = variant_of<V>();
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
    add_derivatives<V>(variant);
#endif
#if SWEEPGEN_MODULE_HAS_CUDA
    add_cuda(variant);
#endif
    return variant;
  }();
  return &v;
}

#if SWEEPGEN_MODULE_HAS_F64
SWEEPGEN_MODULE_VARIANT(F64, f64);
#endif
#if SWEEPGEN_MODULE_HAS_F32
SWEEPGEN_MODULE_VARIANT(F32, f32);
#endif

#define SWEEPGEN_MODULE_TEXT(x) SWEEPGEN_MODULE_TEXT_(x)
#define SWEEPGEN_MODULE_TEXT_(x) #x
#define SWEEPGEN_MODULE_INIT(name) SWEEPGEN_MODULE_INIT_(name)
#define SWEEPGEN_MODULE_INIT_(name) PyInit_##name

}  // namespace

PyMODINIT_FUNC SWEEPGEN_MODULE_INIT(SWEEPGEN_MODULE_NAME)() {
  static sweepgen_python::Scene s;
  s.module_name = SWEEPGEN_MODULE_TEXT(SWEEPGEN_MODULE_NAME);
  s.scene_name = SWEEPGEN_MODULE_TEXT(SWEEPGEN_MODULE_SCENE);
  s.flat_in_layout = SWEEPGEN_MODULE_FLAT_IN;
  s.flat_out_layout = SWEEPGEN_MODULE_FLAT_OUT;
  s.torch_layer = sweepgen_module_torch_layer;
  s.dof = scene::dof;
  s.nq = scene::nq;  // values of q: dof, or a floating base's world_R_base (9) and the joints'
  s.nv = scene::nv;  // values of qd: dof, less the coupled <mimic> joints (mimic: coupled)
  s.constraints = scene::constraints;
  s.checks_inputs = scene::checks_inputs;
  s.status_ok = static_cast<unsigned>(scene::status_ok);
  s.status_constraint_rank_deficient = scene::status_constraint_rank_deficient;
  s.status_saturated = scene::status_saturated;
  s.status_not_finite = scene::status_not_finite;
  s.status_joint_inertia_singular = scene::status_joint_inertia_singular;
#if SWEEPGEN_MODULE_HAS_F64
  s.f64 = described<F64>();
#endif
#if SWEEPGEN_MODULE_HAS_F32
  s.f32 = described<F32>();
#endif
  return sweepgen_python::make_module(s);
}
