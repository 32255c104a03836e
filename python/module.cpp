// The Python module of one generated scene solver (README, "Python"), built by
// sweepgen_add_python_module() (cmake/SweepgenAddPythonModule.cmake). One source for every scene:
// the module name comes from SWEEPGEN_MODULE_NAME, everything else from the generated header
// through sweepgen_module_scene.hpp, which the CMake function writes per module:
//   SWEEPGEN_MODULE_SCENE      the scene's C++ namespace (the scene's `solver:` entry)
//   SWEEPGEN_MODULE_HAS_F64/32 whether the header has namespace f64 / f32 (the scene's `scalars:`)
//   SWEEPGEN_MODULE_FLAT_IN/OUT the flat layout as the header's comment states it
//   SWEEPGEN_MODULE_HAS_DERIVATIVES whether the header has the derivative functions (scene key derivatives)
// `<module>.torch` is python/torch_layer.py (README, "PyTorch"), run the first time it is read.
// Only the generated API common to every scene is bound (and, with derivatives, `derivatives`): dof, nq, nv, constraints, checks_inputs, Status,
// and per scalar outward, decompose (through drivers_from_flat), the solves and flat_solves
// tables and the Solution members nu (when constraints > 0), qdd, tau_ctrl, tau_cmd,
// tip_acceleration, set_acceleration (when the scene lists constraint sets), closure_error (when it has sets
// between two links), saturated,
// dropped_pivots, locked_joints and status. What `expose: all` adds to State and Solution is not
// bound.
//
// Every array argument is 1-D (one state, or shared by every row) or 2-D (K, width) (one row per
// state); a call with any 2-D argument is batched, loops in C++ with the GIL released, and returns
// (K, ...) arrays.
#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sweepgen_module_scene.hpp"

namespace py = pybind11;
namespace scene = SWEEPGEN_MODULE_SCENE;

namespace {

static_assert(scene::returns_every_output,
              "the Python module binds every result of a solve: leave the scene key 'outputs' out, or list them all");
constexpr int dof = scene::dof;
constexpr int nq = scene::nq;  // values of q: dof, or a floating base's world_R_base (9) and the joints'
constexpr int nv = scene::nv;  // values of qd: dof, less the coupled <mimic> joints (mimic: coupled)
constexpr int constraints = scene::constraints;

// Entries of Solution::set_acceleration (6 per listed constraint set), 0 when it has none.
template <class Solution, class = void>
struct SetAccelerationSize : std::integral_constant<int, 0> {};
template <class Solution>
struct SetAccelerationSize<Solution, std::void_t<decltype(&Solution::set_acceleration)>>
    : std::integral_constant<int, static_cast<int>(std::extent_v<decltype(Solution::set_acceleration)>)> {};
// Entries of Solution::closure_error (12 per set between two links), 0 when it has none.
template <class Solution, class = void>
struct ClosureErrorSize : std::integral_constant<int, 0> {};
template <class Solution>
struct ClosureErrorSize<Solution, std::void_t<decltype(&Solution::closure_error)>>
    : std::integral_constant<int, static_cast<int>(std::extent_v<decltype(Solution::closure_error)>)> {};

// Entries of Solution::coupling_torque (one per coupled <mimic> joint), 0 when it has none.
template <class Solution, class = void>
struct CouplingTorqueSize : std::integral_constant<int, 0> {};
template <class Solution>
struct CouplingTorqueSize<Solution, std::void_t<decltype(&Solution::coupling_torque)>>
    : std::integral_constant<int, static_cast<int>(std::extent_v<decltype(Solution::coupling_torque)>)> {};

// The Status flags by name (the generated header's enum Status), for Python and for messages.
struct Flag {
  const char* name;
  unsigned value;
};
constexpr Flag kFlags[] = {
    {"constraint_rank_deficient", scene::status_constraint_rank_deficient},
    {"saturated", scene::status_saturated},
    {"not_finite", scene::status_not_finite},
    {"joint_inertia_singular", scene::status_joint_inertia_singular},
};

std::string flag_names(unsigned status) {
  std::string names;
  for (const Flag& flag : kFlags)
    if (status & flag.value) names += (names.empty() ? "" : "|") + std::string(flag.name);
  return names.empty() ? "ok" : names;
}

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// One array argument: `width` values per row, 1-D (one row, shared by every row of a batched
// call) or 2-D (K rows).
template <class Scalar>
struct Rows {
  const char* name = "";
  py::ssize_t width = 0;
  py::array_t<Scalar, py::array::c_style> array;  // empty for an absent argument of width 0
  bool batched = false;
  py::ssize_t rows = 1;

  const Scalar* row(py::ssize_t k) const {
    static const Scalar none{};  // what an empty argument points to (the generated code reads nothing)
    if (width == 0) return &none;
    return array.data() + (batched ? k * width : 0);
  }
};

// `object` as Rows: real numbers (integers and floats; converted to Scalar), shape (width,) or
// (K, width); None only where width is 0. ValueError naming the argument otherwise.
template <class Scalar>
Rows<Scalar> rows_of(const py::handle& object, const char* name, py::ssize_t width) {
  Rows<Scalar> r;
  r.name = name;
  r.width = width;
  const std::string expected = "expected shape (" + std::to_string(width) + ",) or (K, " + std::to_string(width) + ")";
  if (object.is_none()) {
    if (width != 0) throw py::value_error(std::string(name) + ": required, " + expected);
    return r;
  }
  const py::array any = py::array::ensure(object);
  if (!any) throw py::value_error(std::string(name) + ": not convertible to an array, " + expected);
  const char kind = any.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::value_error(std::string(name) + ": expected real numbers, got dtype " +
                          py::str(any.dtype()).cast<std::string>());
  if (!(any.ndim() == 1 || any.ndim() == 2) || any.shape(any.ndim() - 1) != width)
    throw py::value_error(std::string(name) + ": " + expected + ", got " + shape_text(any));
  r.array = py::array_t<Scalar, py::array::c_style | py::array::forcecast>::ensure(any);
  if (!r.array)
    throw py::value_error(std::string(name) + ": not convertible to " +
                          py::str(py::dtype::of<Scalar>()).cast<std::string>());
  r.batched = any.ndim() == 2;
  r.rows = r.batched ? any.shape(0) : 1;
  return r;
}

// Rows of a call: the common K of its 2-D arguments (1-D ones are shared); `batched` when any is 2-D.
struct Batch {
  bool batched = false;
  py::ssize_t rows = 1;
};

template <class Scalar>
Batch batch_of(std::initializer_list<const Rows<Scalar>*> arguments, Batch batch = {}) {
  const char* first = nullptr;
  for (const Rows<Scalar>* a : arguments) {
    if (!a->batched) continue;
    if (batch.batched && a->rows != batch.rows)
      throw py::value_error(std::string(a->name) + ": " + std::to_string(a->rows) + " rows, but " +
                            (first ? first : "the state") + " has " + std::to_string(batch.rows));
    if (!batch.batched) first = a->name;
    batch = {true, a->rows};
  }
  return batch;
}

// Runs body(k) for every row, without the GIL when batched (body touches no Python object).
template <class Body>
void for_each_row(const Batch& batch, Body&& body) {
  std::optional<py::gil_scoped_release> release;
  if (batch.batched) release.emplace();
  for (py::ssize_t k = 0; k < batch.rows; ++k) body(k);
}

template <class T>
py::array_t<T> array_of(const Batch& batch, py::ssize_t width) {
  return batch.batched ? py::array_t<T>({batch.rows, width}) : py::array_t<T>({width});
}

// The results of the structured solves: arrays allocated before the loop (with the GIL), filled
// row by row through raw pointers (without it).
template <class Scalar, int set_width, int closure_width, int coupling_width>
class Results {
 public:
  explicit Results(const Batch& batch)
      : batch_(batch),
        qdd_(array_of<Scalar>(batch, dof)),
        tau_cmd_(array_of<Scalar>(batch, dof)),
        tau_ctrl_(array_of<Scalar>(batch, dof)),
        nu_(array_of<Scalar>(batch, constraints)),
        tip_acceleration_(array_of<Scalar>(batch, 6)),
        set_acceleration_(array_of<Scalar>(batch, set_width)),
        closure_error_(array_of<Scalar>(batch, closure_width)),
        coupling_torque_(array_of<Scalar>(batch, coupling_width)),
        saturated_(array_of<bool>(batch, dof)),
        dropped_pivots_(batch.rows),
        locked_joints_(batch.rows),
        status_(batch.rows),
        to_{qdd_.mutable_data(),      tau_cmd_.mutable_data(),        tau_ctrl_.mutable_data(),
            nu_.mutable_data(),       tip_acceleration_.mutable_data(), set_acceleration_.mutable_data(),
            closure_error_.mutable_data(), coupling_torque_.mutable_data(), saturated_.mutable_data(), dropped_pivots_.mutable_data(), locked_joints_.mutable_data(),
            status_.mutable_data()} {}

  template <class Solution>
  void write(py::ssize_t k, const Solution& s) {
    std::copy_n(s.qdd, dof, to_.qdd + k * dof);
    std::copy_n(s.tau_cmd, dof, to_.tau_cmd + k * dof);
    std::copy_n(s.tau_ctrl, dof, to_.tau_ctrl + k * dof);
    if constexpr (constraints > 0) std::copy_n(s.nu, constraints, to_.nu + k * constraints);
    std::copy_n(s.tip_acceleration, 6, to_.tip_acceleration + k * 6);
    if constexpr (set_width > 0) std::copy_n(s.set_acceleration, set_width, to_.set_acceleration + k * set_width);
    if constexpr (closure_width > 0) std::copy_n(s.closure_error, closure_width, to_.closure_error + k * closure_width);
    if constexpr (coupling_width > 0)
      std::copy_n(s.coupling_torque, coupling_width, to_.coupling_torque + k * coupling_width);
    std::copy_n(s.saturated, dof, to_.saturated + k * dof);
    to_.dropped_pivots[k] = s.dropped_pivots;
    to_.locked_joints[k] = s.locked_joints;
    to_.status[k] = s.status;
  }

  unsigned status(py::ssize_t k) const { return to_.status[k]; }

  // {qdd, tau_cmd, tau_ctrl, nu, tip_acceleration, (set_acceleration,) (closure_error,) (coupling_torque,) saturated, dropped_pivots,
  // locked_joints, status}: (K, ...) arrays when batched, else 1-D arrays and Python ints.
  py::dict dict() const {
    const auto per_row = [&](const auto& values) -> py::object {
      if (batch_.batched) return values;
      return py::int_(values.at(0));
    };
    py::dict d;
    d["qdd"] = qdd_;
    d["tau_cmd"] = tau_cmd_;
    d["tau_ctrl"] = tau_ctrl_;
    d["nu"] = nu_;
    d["tip_acceleration"] = tip_acceleration_;
    if (set_width > 0) d["set_acceleration"] = set_acceleration_;
    if (closure_width > 0) d["closure_error"] = closure_error_;
    if (coupling_width > 0) d["coupling_torque"] = coupling_torque_;
    d["saturated"] = saturated_;
    d["dropped_pivots"] = per_row(dropped_pivots_);
    d["locked_joints"] = per_row(locked_joints_);
    d["status"] = per_row(status_);
    return d;
  }

 private:
  struct Pointers {
    Scalar *qdd, *tau_cmd, *tau_ctrl, *nu, *tip_acceleration, *set_acceleration, *closure_error, *coupling_torque;
    bool* saturated;
    std::int32_t *dropped_pivots, *locked_joints;
    std::uint32_t* status;
  };
  Batch batch_;
  py::array_t<Scalar> qdd_, tau_cmd_, tau_ctrl_, nu_, tip_acceleration_, set_acceleration_, closure_error_, coupling_torque_;
  py::array_t<bool> saturated_;
  py::array_t<std::int32_t> dropped_pivots_, locked_joints_;
  py::array_t<std::uint32_t> status_;
  Pointers to_;
};

// SolverStatusError (a RuntimeError), created at import.
py::handle status_error;

// Raises SolverStatusError for the first row whose status has a bit of `mask`, carrying
// status, index (None for an unbatched call), policy and result.
template <class StatusOf>
void raise_on_status(unsigned mask, const Batch& batch, StatusOf&& status_of, const std::string& function,
                     const std::string& policy, const py::object& result) {
  if (mask == 0) return;
  py::ssize_t first = -1, flagged = 0;
  for (py::ssize_t k = 0; k < batch.rows; ++k)
    if (status_of(k) & mask) {
      if (first < 0) first = k;
      ++flagged;
    }
  if (first < 0) return;
  const unsigned status = status_of(first);
  std::string message = function + " (policy " + policy + "): status " + std::to_string(status) + " (" +
                        flag_names(status) + ")";
  if (batch.batched)
    message += " at row " + std::to_string(first) + " (" + std::to_string(flagged) + " of " +
               std::to_string(batch.rows) + " rows flagged)";
  message += "; raise_on_status = " + std::to_string(mask);
  py::object error = py::reinterpret_borrow<py::object>(status_error)(message);
  error.attr("status") = status;
  error.attr("index") = batch.batched ? py::object(py::int_(first)) : py::object(py::none());
  error.attr("policy") = policy;
  error.attr("result") = result;
  PyErr_SetObject(status_error.ptr(), error.ptr());
  throw py::error_already_set();
}

// `rows` states through a generated batch entry point (n states in rows of n values, value k of
// state s at [k * n + s]): each state's flat input gathered by `in_row(s, values)` (in_size values),
// its flat output handed to `out_row(s, values)` (out_size values). The batch solves the states
// several at a time in vector lanes (the generated header, "Many states at once").
template <class Scalar, class InRow, class OutRow>
void solve_in_batch(void (*batch)(int, const Scalar*, Scalar*) noexcept, py::ssize_t rows, int in_size, int out_size,
                    InRow&& in_row, OutRow&& out_row) {
  if (rows > std::numeric_limits<int>::max()) throw py::value_error("more states than a batch call takes (2^31 - 1)");
  const auto n = static_cast<std::size_t>(rows);
  std::vector<Scalar> in(n * static_cast<std::size_t>(in_size)), out(n * static_cast<std::size_t>(out_size)), row;
  row.resize(static_cast<std::size_t>(std::max(in_size, out_size)));
  for (std::size_t s = 0; s < n; ++s) {
    in_row(s, row.data());
    for (int k = 0; k < in_size; ++k) in[k * n + s] = row[k];
  }
  batch(static_cast<int>(rows), in.data(), out.data());
  for (std::size_t s = 0; s < n; ++s) {
    for (int k = 0; k < out_size; ++k) row[k] = out[k * n + s];
    out_row(s, row.data());
  }
}

// `rows` states through a generated batch entry point into `out` (out_size values a row, the flat
// output's layout), each state's flat input gathered by `in_row`; without the GIL.
template <class Scalar, class InRow>
void flat_rows_in_batch(void (*batch)(int, const Scalar*, Scalar*) noexcept, py::ssize_t rows, int in_size,
                        int out_size, InRow&& in_row, Scalar* out) {
  py::gil_scoped_release release;
  solve_in_batch<Scalar>(batch, rows, in_size, out_size, in_row,
                         [&](std::size_t s, const Scalar* from) { std::copy_n(from, out_size, out + s * out_size); });
}

// raise_on_status's status of row k of flat outputs (`width` values a row, the status last).
template <class Scalar>
auto flat_status_of(const Scalar* out, int width) {
  return [out, width](py::ssize_t k) { return static_cast<unsigned>(out[k * width + width - 1]); };
}

// solve_in_batch's `in_row` for a state given as its parts: row s's q, qd, drivers and beta, in the
// flat input's order.
template <class Scalar>
auto flat_input_of(const Rows<Scalar>& q, const Rows<Scalar>& qd, const Rows<Scalar>& drivers,
                   const Rows<Scalar>& beta) {
  return [&](std::size_t s, Scalar* to) {
    const auto k = static_cast<py::ssize_t>(s);
    to = std::copy_n(q.row(k), q.width, to);
    to = std::copy_n(qd.row(k), qd.width, to);
    to = std::copy_n(drivers.row(k), drivers.width, to);
    std::copy_n(beta.row(k), beta.width, to);
  };
}

// Index of `policy` in a generated table ({policy, function} entries); ValueError listing them.
template <class Table>
std::size_t policy_index(const Table& table, const std::string& policy) {
  std::string known;
  for (std::size_t k = 0; k < std::size(table); ++k) {
    if (policy == table[k].policy) return k;
    known += (k ? ", " : "") + std::string(table[k].policy);
  }
  throw py::value_error("policy: '" + policy + "' is not a policy of this scene (" + known + ")");
}

// One scalar variant of the generated code (namespace f64 or f32): types, sizes, entry points.
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
    static void decompose(const Scalar* drivers, State& s) {                                             \
      scene::tag::decompose(scene::tag::drivers_from_flat(drivers), s);                                  \
    }                                                                                                    \
  }

#if SWEEPGEN_MODULE_HAS_DERIVATIVES
// The derivative functions of a variant (scene key derivatives): derivative_solves, by policy.
#define SWEEPGEN_MODULE_DERIVATIVES(Name, tag)                                                           \
  struct Name {                                                                                          \
    using Scalar = scene::tag::Scalar;                                                                   \
    using Derivatives = scene::tag::Derivatives;                                                         \
    static constexpr int columns = scene::tag::derivative_columns;                                       \
    static constexpr bool of_qdd = scene::tag::derivative_of_qdd, of_nu = scene::tag::derivative_of_nu;   \
    static constexpr bool of_tau_cmd = scene::tag::derivative_of_tau_cmd;                                \
    static constexpr const auto& solves = scene::tag::derivative_solves;                                 \
    static constexpr const auto& batch_solves = scene::tag::derivative_batch_solves;                     \
    static constexpr int flat_in_size = scene::tag::flat_in_size;                                        \
    static constexpr int flat_out_size = scene::tag::derivative_flat_out_size;                           \
    static constexpr const auto& all_solves = scene::tag::solves;                                        \
    static auto drivers_from_flat(const Scalar* drivers) { return scene::tag::drivers_from_flat(drivers); } \
  }

// Index of `policy` among a variant's derivative functions. A policy of the scene without one is
// not differentiable (docs/generated-code.md, "Derivatives": the saturating policies clamp, a kink in the solve):
// the ValueError says so, not that the scene lacks the policy.
template <class Derived>
std::size_t derivative_index(const std::string& policy) {
  std::string differentiable;
  for (std::size_t k = 0; k < std::size(Derived::solves); ++k) {
    if (policy == Derived::solves[k].policy) return k;
    differentiable += (k ? ", " : "") + std::string(Derived::solves[k].policy);
  }
  for (const auto& entry : Derived::all_solves)
    if (policy == entry.policy)
      throw py::value_error("policy: '" + policy + "' is a policy of this scene but is not differentiable: it clamps "
                            "torques at their limits, a kink in the solve, so no derivatives are generated for it "
                            "(derivatives of this scene: " + differentiable + ")");
  return policy_index(Derived::solves, policy);
}

// derivatives(): the values and the Jacobians of one state or K, split by the columns of (D2):
// d_<y>_dq (rows, nv), d_<y>_dqd (rows, nv), d_<y>_dtau_ff (rows, dof), d_<y>_dbeta (rows,
// constraints), each (K, rows, columns) when batched; y the outputs the scene asks Jacobians of
// (derivative_outputs).
template <class Derived>
void bind_derivatives(py::module_& m, const std::string& prefix, py::ssize_t n_drivers) {
  using Scalar = typename Derived::Scalar;
  py::list policies;
  for (const auto& entry : Derived::solves) policies.append(entry.policy);
  m.attr("derivative_policies") = py::tuple(policies);
  m.attr("derivative_columns") = Derived::columns;
  // Per output y: its name, its rows and whether its Jacobian is returned (the header's derivative_of_*).
  static constexpr std::tuple<const char*, py::ssize_t, bool> kOutputs[] = {
      {"qdd", dof, Derived::of_qdd}, {"nu", constraints, Derived::of_nu}, {"tau_cmd", dof, Derived::of_tau_cmd}};
  py::list returned;
  for (const auto& [name, rows, with_jacobian] : kOutputs)
    if (with_jacobian && rows > 0) returned.append(name);
  m.attr("derivative_outputs") = py::tuple(returned);
  m.def(
      "derivatives",
      [prefix, n_drivers](const py::object& q, const py::object& qd, const py::object& drivers, const py::object& beta,
                          const std::string& policy, unsigned mask) {
        const Rows<Scalar> q_rows = rows_of<Scalar>(q, "q", nq), qd_rows = rows_of<Scalar>(qd, "qd", nv),
                           d = rows_of<Scalar>(drivers, "drivers", n_drivers),
                           b = rows_of<Scalar>(beta, "beta", constraints);
        const std::size_t index = derivative_index<Derived>(policy);
        const Batch batch = batch_of<Scalar>({&q_rows, &qd_rows, &d, &b});
        constexpr py::ssize_t columns = Derived::columns;
        // Per output y (rows r): its values and its four column blocks, (D2)'s order.
        struct Output {
          const char* name;
          py::ssize_t rows;
          bool with_jacobian;
          py::array_t<Scalar> values, blocks[4];
        };
        const py::ssize_t widths[4] = {nv, nv, dof, constraints};
        const char* suffixes[4] = {"_dq", "_dqd", "_dtau_ff", "_dbeta"};
        std::vector<Output> outputs;
        for (const auto& [name, rows, with_jacobian] : kOutputs) {
          Output o{name, rows, with_jacobian, array_of<Scalar>(batch, rows), {}};
          for (int k = 0; k < 4; ++k)
            if (with_jacobian)
              o.blocks[k] = batch.batched ? py::array_t<Scalar>({batch.rows, rows, widths[k]}) : py::array_t<Scalar>({rows, widths[k]});
          outputs.push_back(std::move(o));
        }
        py::array_t<std::uint32_t> status(batch.rows);
        std::vector<Scalar*> values_to, blocks_to;
        for (auto& o : outputs) {
          values_to.push_back(o.values.mutable_data());
          for (auto& block : o.blocks) blocks_to.push_back(o.with_jacobian ? block.mutable_data() : nullptr);
        }
        std::uint32_t* status_to = status.mutable_data();
        // Row k's values (qdd, nu, tau_cmd), the Jacobians returned and its status, into the outputs.
        const auto store = [&](py::ssize_t k, const Scalar* const values[3], const Scalar* const jacobians[3],
                               std::uint32_t row_status) {
          for (std::size_t o = 0; o < 3; ++o) {
            const py::ssize_t rows = outputs[o].rows;
            if (rows == 0) continue;
            std::copy_n(values[o], rows, values_to[o] + k * rows);
            if (!jacobians[o]) continue;
            py::ssize_t first = 0;
            for (int block = 0; block < 4; ++block) {
              Scalar* to = blocks_to[4 * o + block] + k * rows * widths[block];
              for (py::ssize_t row = 0; row < rows; ++row)
                std::copy_n(jacobians[o] + row * columns + first, widths[block], to + row * widths[block]);
              first += widths[block];
            }
          }
          status_to[k] = row_status;
        };
        if (batch.batched) {  // the batch entry point, without the GIL: flat rows in and out
          py::gil_scoped_release release;
          solve_in_batch<Scalar>(
              Derived::batch_solves[index].solve, batch.rows, Derived::flat_in_size, Derived::flat_out_size,
              flat_input_of(q_rows, qd_rows, d, b),
              [&](std::size_t s, const Scalar* from) {
                // The derivative flat output: qdd, nu, tau_cmd, then the Jacobians returned, status.
                const Scalar* values[3] = {from, constraints > 0 ? from + dof : nullptr, from + dof + constraints};
                const Scalar* jacobians[3] = {nullptr, nullptr, nullptr};
                from += 2 * dof + constraints;
                for (std::size_t o = 0; o < 3; ++o)
                  if (std::get<2>(kOutputs[o]) && std::get<1>(kOutputs[o]) > 0) {
                    jacobians[o] = from;
                    from += std::get<1>(kOutputs[o]) * columns;
                  }
                store(static_cast<py::ssize_t>(s), values, jacobians, static_cast<std::uint32_t>(*from));
              });
        } else {
          typename Derived::Derivatives r;
          Derived::solves[index].solve(q_rows.row(0), qd_rows.row(0), Derived::drivers_from_flat(d.row(0)), b.row(0), r);
          const Scalar* values[3] = {r.qdd, nullptr, r.tau_cmd};
          const Scalar* jacobians[3] = {nullptr, nullptr, nullptr};
          if constexpr (constraints > 0) values[1] = r.nu;
          if constexpr (Derived::of_qdd) jacobians[0] = r.d_qdd;
          if constexpr (constraints > 0 && Derived::of_nu) jacobians[1] = r.d_nu;
          if constexpr (Derived::of_tau_cmd) jacobians[2] = r.d_tau_cmd;
          store(0, values, jacobians, r.status);
        }
        py::dict result;
        for (const auto& o : outputs) {
          result[o.name] = o.values;
          if (!o.with_jacobian) continue;
          for (int block = 0; block < 4; ++block) result[py::str(std::string("d_") + o.name + suffixes[block])] = o.blocks[block];
        }
        result["status"] = batch.batched ? py::object(status) : py::object(py::int_(status.at(0)));
        raise_on_status(mask, batch, [&](py::ssize_t k) { return status_to[k]; }, prefix + "derivatives", policy, result);
        return result;
      },
      py::arg("q"), py::arg("qd"), py::arg("drivers") = py::none(), py::arg("beta") = py::none(), py::kw_only(),
      py::arg("policy") = Derived::solves[0].policy, py::arg("raise_on_status") = 0u,
      "The generated derivatives_<policy> (scene key derivatives): arguments as solve(). Returns a dict: qdd, nu, "
      "tau_cmd and, for each y of derivative_outputs, d_y_dq, d_y_dqd (rows, nv), d_y_dtau_ff (rows, dof) and d_y_dbeta (rows, constraints) "
      "(K, rows, columns) when batched: a floating base's first six q columns are its rotation vector in its own "
      "frame and its position (docs/derivation.md, D2); status.");
}
#endif

// The flat input between q, qd and beta: the drivers (SWEEPGEN_MODULE_FLAT_IN).
template <class Api>
constexpr int drivers_size = Api::flat_in_size - nq - nv - constraints;

// outward() and decompose() results of one state or of K (a batched outward()).
template <class Api>
struct StateBatch {
  std::vector<typename Api::State> states;
  bool batched = false;
  bool decomposed = false;

  Batch batch() const { return {batched, static_cast<py::ssize_t>(states.size())}; }
  const typename Api::State& at(py::ssize_t k) const { return states[batched ? static_cast<std::size_t>(k) : 0]; }
};

template <class Api>
void bind_variant(py::module_& module, const char* doc) {
  using Scalar = typename Api::Scalar;
  using State = StateBatch<Api>;
  constexpr py::ssize_t n_drivers = drivers_size<Api>;
  py::module_ m = module.def_submodule(Api::name, doc);
  const std::string prefix = module.attr("__name__").cast<std::string>() + "." + Api::name + ".";

  py::list policies;
  for (const auto& entry : Api::solves) policies.append(entry.policy);
  const std::string default_policy = Api::solves[0].policy;
  m.attr("dof") = dof;
  m.attr("nq") = nq;
  m.attr("nv") = nv;
  m.attr("constraints") = constraints;
  m.attr("drivers_size") = n_drivers;
  m.attr("flat_in_size") = Api::flat_in_size;
  m.attr("flat_out_size") = Api::flat_out_size;
  m.attr("policies") = py::tuple(policies);
  m.attr("dtype") = py::dtype::of<Scalar>();

  py::class_<State>(m, "State",
                    "outward() (and decompose()) results of one state, or of K states for 2-D q and qd. Opaque: "
                    "made by outward(), completed by decompose(), read by solve_state().")
      .def_property_readonly("batched", [](const State& s) { return s.batched; })
      .def_property_readonly("decomposed", [](const State& s) { return s.decomposed; })
      .def("__len__", [](const State& s) { return s.states.size(); });

  m.def(
      "outward",
      [](const py::object& q, const py::object& qd) {
        const Rows<Scalar> q_rows = rows_of<Scalar>(q, "q", nq), qd_rows = rows_of<Scalar>(qd, "qd", nv);
        const Batch batch = batch_of<Scalar>({&q_rows, &qd_rows});
        State state;
        state.batched = batch.batched;
        state.states.resize(static_cast<std::size_t>(batch.rows));
        for_each_row(batch, [&](py::ssize_t k) { Api::outward(q_rows.row(k), qd_rows.row(k), state.states[k]); });
        return state;
      },
      py::arg("q"), py::arg("qd"),
      "Outward sweep: everything that depends on q, qd only. q: (nq,) or (K, nq), qd: (nv,) or (K, nv). Returns a State.");

  m.def(
      "decompose",
      [](State& state, const py::object& drivers) {
        const Rows<Scalar> d = rows_of<Scalar>(drivers, "drivers", n_drivers);
        if (d.batched && !state.batched)
          throw py::value_error("drivers: 2-D drivers need a batched state (outward() of 2-D q, qd)");
        const Batch batch = batch_of<Scalar>({&d}, state.batch());
        for_each_row(batch, [&](py::ssize_t k) { Api::decompose(d.row(k), state.states[k]); });
        state.decomposed = true;
      },
      py::arg("state"), py::arg("drivers") = py::none(),
      "Decomposition over the drivers, in place. drivers: (drivers_size,) or (K, drivers_size), the flat "
      "input after q and qd, without beta (module flat_in_layout); None when drivers_size is 0.");

  m.def(
      "solve_state",
      [prefix](const State& state, const py::object& beta, const std::string& policy, unsigned mask) {
        const Rows<Scalar> b = rows_of<Scalar>(beta, "beta", constraints);
        if (!state.decomposed) throw py::value_error("state: decompose() has not run on it");
        const auto solve = Api::solves[policy_index(Api::solves, policy)].solve;
        const Batch batch = batch_of<Scalar>({&b}, state.batched ? state.batch() : Batch{});
        Results<Scalar, SetAccelerationSize<typename Api::Solution>::value, ClosureErrorSize<typename Api::Solution>::value,
                CouplingTorqueSize<typename Api::Solution>::value>
            results(batch);
        for_each_row(batch, [&](py::ssize_t k) {
          typename Api::Solution solution;
          solve(state.at(k), b.row(k), solution);
          results.write(k, solution);
        });
        const py::dict result = results.dict();
        raise_on_status(mask, batch, [&](py::ssize_t k) { return results.status(k); }, prefix + "solve_state", policy,
                        result);
        return result;
      },
      py::arg("state"), py::arg("beta") = py::none(), py::kw_only(), py::arg("policy") = default_policy,
      py::arg("raise_on_status") = 0u,
      "The solver sweep (the re-solve): a decomposed State and setpoints beta, (constraints,) or (K, "
      "constraints) (None when constraints is 0); a single state with K setpoint rows solves it K times. "
      "Returns a dict of arrays (see solve()).");

  m.def(
      "solve",
      [prefix](const py::object& q, const py::object& qd, const py::object& drivers, const py::object& beta,
         const std::string& policy, unsigned mask) {
        const Rows<Scalar> q_rows = rows_of<Scalar>(q, "q", nq), qd_rows = rows_of<Scalar>(qd, "qd", nv),
                           d = rows_of<Scalar>(drivers, "drivers", n_drivers),
                           b = rows_of<Scalar>(beta, "beta", constraints);
        const auto solve = Api::solves[policy_index(Api::solves, policy)].solve;
        const Batch batch = batch_of<Scalar>({&q_rows, &qd_rows, &d, &b});
        Results<Scalar, SetAccelerationSize<typename Api::Solution>::value, ClosureErrorSize<typename Api::Solution>::value,
                CouplingTorqueSize<typename Api::Solution>::value>
            results(batch);
        for_each_row(batch, [&](py::ssize_t k) {
          typename Api::State state;
          typename Api::Solution solution;
          Api::outward(q_rows.row(k), qd_rows.row(k), state);
          Api::decompose(d.row(k), state);
          solve(state, b.row(k), solution);
          results.write(k, solution);
        });
        const py::dict result = results.dict();
        raise_on_status(mask, batch, [&](py::ssize_t k) { return results.status(k); }, prefix + "solve", policy,
                        result);
        return result;
      },
      py::arg("q"), py::arg("qd"), py::arg("drivers") = py::none(), py::arg("beta") = py::none(), py::kw_only(),
      py::arg("policy") = default_policy, py::arg("raise_on_status") = 0u,
      "outward + decompose + solve_<policy>. q: (nq,), qd: (nv,); drivers: (drivers_size,); beta: (constraints,); "
      "each also (K, width) for K states (1-D ones shared by every row). Returns a dict: qdd, tau_cmd, "
      "tau_ctrl (dof), nu (constraints), tip_acceleration (6), saturated (dof, bool), dropped_pivots, "
      "locked_joints, status (ints; (K,) arrays when batched). raise_on_status: a mask of Status flags; "
      "a row with any of them raises SolverStatusError.");

  m.def(
      "solve_flat",
      [prefix](const py::object& in, const std::string& policy, unsigned mask) {
        const Rows<Scalar> in_rows = rows_of<Scalar>(in, "in", Api::flat_in_size);
        const std::size_t index = policy_index(Api::flat_solves, policy);
        const Batch batch = batch_of<Scalar>({&in_rows});
        py::array_t<Scalar> out = array_of<Scalar>(batch, Api::flat_out_size);
        Scalar* out_data = out.mutable_data();
        if (batch.batched) {  // the batch entry point
          flat_rows_in_batch<Scalar>(
              Api::batch_solves[index].solve, batch.rows, Api::flat_in_size, Api::flat_out_size,
              [&](std::size_t s, Scalar* to) { std::copy_n(in_rows.row(static_cast<py::ssize_t>(s)), Api::flat_in_size, to); },
              out_data);
        } else {
          Api::flat_solves[index].solve(in_rows.row(0), out_data);
        }
        raise_on_status(mask, batch, flat_status_of(out_data, Api::flat_out_size), prefix + "solve_flat", policy, out);
        return out;
      },
      py::arg("in"), py::kw_only(), py::arg("policy") = default_policy, py::arg("raise_on_status") = 0u,
      "The generated flat entry point: in (flat_in_size,) or (K, flat_in_size) -> out (flat_out_size,) or "
      "(K, flat_out_size), layouts in the module's flat_in_layout and flat_out_layout (status last). K rows go "
      "through the generated solve_<policy>_batch: several states per vector instruction.");

  m.def(
      "solve_batch",
      [prefix](const py::object& q, const py::object& qd, const py::object& drivers, const py::object& beta,
               const std::string& policy, unsigned mask) {
        const Rows<Scalar> q_rows = rows_of<Scalar>(q, "q", nq), qd_rows = rows_of<Scalar>(qd, "qd", nv),
                           d = rows_of<Scalar>(drivers, "drivers", n_drivers),
                           b = rows_of<Scalar>(beta, "beta", constraints);
        const std::size_t index = policy_index(Api::flat_solves, policy);
        const Batch batch{true, batch_of<Scalar>({&q_rows, &qd_rows, &d, &b}).rows};
        py::array_t<Scalar> out = array_of<Scalar>(batch, Api::flat_out_size);
        Scalar* out_data = out.mutable_data();
        flat_rows_in_batch<Scalar>(Api::batch_solves[index].solve, batch.rows, Api::flat_in_size, Api::flat_out_size,
                                   flat_input_of(q_rows, qd_rows, d, b), out_data);
        raise_on_status(mask, batch, flat_status_of(out_data, Api::flat_out_size), prefix + "solve_batch", policy, out);
        return out;
      },
      py::arg("q"), py::arg("qd"), py::arg("drivers") = py::none(), py::arg("beta") = py::none(), py::kw_only(),
      py::arg("policy") = default_policy, py::arg("raise_on_status") = 0u,
      "The generated solve_<policy>_batch on K states given as solve()'s arguments, without forming their flat "
      "input first: q, qd, drivers, beta as solve() takes them (at least one 2-D, or K = 1) -> out (K, "
      "flat_out_size), solve_flat()'s layout. What the PyTorch layer's forward calls.");
}

#if SWEEPGEN_MODULE_HAS_F64
SWEEPGEN_MODULE_VARIANT(F64, f64);
#endif
#if SWEEPGEN_MODULE_HAS_F32
SWEEPGEN_MODULE_VARIANT(F32, f32);
#endif
#if SWEEPGEN_MODULE_HAS_DERIVATIVES && SWEEPGEN_MODULE_HAS_F64
SWEEPGEN_MODULE_DERIVATIVES(F64Derivatives, f64);
#endif
#if SWEEPGEN_MODULE_HAS_DERIVATIVES && SWEEPGEN_MODULE_HAS_F32
SWEEPGEN_MODULE_DERIVATIVES(F32Derivatives, f32);
#endif

}  // namespace

PYBIND11_MODULE(SWEEPGEN_MODULE_NAME, m) {
  const std::string name = PYBIND11_TOSTRING(SWEEPGEN_MODULE_NAME);
  m.doc() = "The sweepgen-generated solver " PYBIND11_TOSTRING(SWEEPGEN_MODULE_SCENE)
            " (README, \"Python\"): submodules f64 and/or f32 with outward, decompose, solve_state, solve, "
            "solve_flat and solve_batch. Flat input: [" SWEEPGEN_MODULE_FLAT_IN "]; the drivers are the part after q and qd, "
            "without beta.";
  m.attr("dof") = dof;
  m.attr("nq") = nq;
  m.attr("nv") = nv;
  m.attr("constraints") = constraints;
  m.attr("checks_inputs") = scene::checks_inputs;
  m.attr("flat_in_layout") = SWEEPGEN_MODULE_FLAT_IN;
  m.attr("flat_out_layout") = SWEEPGEN_MODULE_FLAT_OUT;

  py::dict flags;
  flags["ok"] = static_cast<unsigned>(scene::status_ok);
  for (const Flag& flag : kFlags) flags[flag.name] = flag.value;
  m.attr("Status") = py::module_::import("enum").attr("IntFlag")("Status", flags, py::arg("module") = name);

  const py::module_ builtins = py::module_::import("builtins");
  py::dict members;
  members["__module__"] = name;
  members["__doc__"] =
      "A solve returned a status with a flag of raise_on_status. Attributes: status (int), index (the first "
      "flagged row of a batched call, else None), policy, result (what the call would have returned).";
  py::object error = builtins.attr("type")("SolverStatusError", py::make_tuple(builtins.attr("RuntimeError")), members);
  m.attr("SolverStatusError") = error;
  status_error = error.release();  // lives as long as the process, like the module

  py::list scalars;
#if SWEEPGEN_MODULE_HAS_F64
  bind_variant<F64>(m, "double arithmetic");
  scalars.append("f64");
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
  {
    py::module_ sub = m.attr("f64");
    bind_derivatives<F64Derivatives>(sub, name + ".f64.", drivers_size<F64>);
  }
#endif
#endif
#if SWEEPGEN_MODULE_HAS_F32
  bind_variant<F32>(m, "float arithmetic");
  scalars.append("f32");
#if SWEEPGEN_MODULE_HAS_DERIVATIVES
  {
    py::module_ sub = m.attr("f32");
    bind_derivatives<F32Derivatives>(sub, name + ".f32.", drivers_size<F32>);
  }
#endif
#endif
  m.attr("scalars") = py::tuple(scalars);

  // <module>.torch: the PyTorch layer (python/torch_layer.py), run on first use (a module-level
  // __getattr__, PEP 562), so that importing the module never imports torch.
  m.def("__getattr__", [name](const std::string& attribute) -> py::object {
    if (attribute != "torch") throw py::attribute_error("module '" + name + "' has no attribute '" + attribute + "'");
    py::module_ self = py::module_::import(name.c_str());
    py::dict scope;
    scope["__name__"] = name + ".torch";
    scope["__builtins__"] = py::module_::import("builtins");
    try {
      py::exec(sweepgen_module_torch_layer, scope);
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_ImportError)) throw;
      const std::string python = py::str(py::module_::import("sys").attr("executable"));
      throw py::import_error(name + ".torch needs PyTorch in " + python + " (Debian: python3-torch): " + e.what());
    }
    py::object layer = scope["bind"](self);
    self.attr("torch") = layer;
    return layer;
  });
}
