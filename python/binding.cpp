// The binding of every scene's Python module (README, "Python"), compiled once per build and linked
// into each module by sweepgen_add_python_module() (cmake/SweepgenAddPythonModule.cmake): a module's
// own source, python/module.cpp, describes its scene (python/module_api.hpp) and calls make_module.
// `<module>.torch` is python/torch_layer.py (README, "PyTorch"), run the first time it is read.
// Only the generated API common to every scene is bound (and, with derivatives, `derivatives`): dof, nq, nv, constraints, checks_inputs, Status,
// and per scalar outward, decompose (through drivers_from_flat), the solves and flat_solves
// tables and the Solution members nu (when constraints > 0), qdd, tau_ctrl, tau_cmd,
// tip_acceleration, set_acceleration (when the scene lists constraint sets), closure_error (when it has sets
// between two links), coupling_torque (when it has coupled joints), saturated,
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
#include <cstring>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "module_api.hpp"

namespace py = pybind11;

namespace sweepgen_python {
namespace {

// The Status flags by name (the generated header's enum Status), for Python and for messages.
struct Flag {
  const char* name;
  unsigned value;
};
std::vector<Flag> flags_of(const Scene& scene) {
  return {{"constraint_rank_deficient", scene.status_constraint_rank_deficient},
          {"saturated", scene.status_saturated},
          {"not_finite", scene.status_not_finite},
          {"joint_inertia_singular", scene.status_joint_inertia_singular}};
}
// The module's flags (set at import: one module per shared object, each with its own copy of this file).
std::vector<Flag> status_flags;

std::string flag_names(unsigned status) {
  std::string names;
  for (const Flag& flag : status_flags)
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
// row by row from a Solution's bytes (the variant's member offsets) through raw pointers (without it).
template <class Scalar>
class Results {
 public:
  Results(const Variant<Scalar>& v, const Batch& batch)
      : v_(v),
        batch_(batch),
        arrays_{array_of<Scalar>(batch, v.qdd.width),          array_of<Scalar>(batch, v.tau_cmd.width),
                array_of<Scalar>(batch, v.tau_ctrl.width),     array_of<Scalar>(batch, v.nu.width),
                array_of<Scalar>(batch, v.tip_acceleration.width), array_of<Scalar>(batch, v.set_acceleration.width),
                array_of<Scalar>(batch, v.closure_error.width), array_of<Scalar>(batch, v.coupling_torque.width)},
        saturated_(array_of<bool>(batch, v.saturated.width)),
        dropped_pivots_(batch.rows),
        locked_joints_(batch.rows),
        status_(batch.rows),
        members_{v.qdd, v.tau_cmd, v.tau_ctrl, v.nu, v.tip_acceleration, v.set_acceleration, v.closure_error,
                 v.coupling_torque},
        saturated_to_(saturated_.mutable_data()),
        dropped_pivots_to_(dropped_pivots_.mutable_data()),
        locked_joints_to_(locked_joints_.mutable_data()),
        status_to_(status_.mutable_data()) {
    for (std::size_t a = 0; a < kArrays; ++a) to_[a] = arrays_[a].mutable_data();
  }

  // Row k from a Solution's bytes (without the GIL: raw pointers only).
  void write(py::ssize_t k, const unsigned char* solution) {
    for (std::size_t a = 0; a < kArrays; ++a)
      if (const int width = members_[a].width; width > 0)
        std::memcpy(to_[a] + k * width, solution + members_[a].offset, sizeof(Scalar) * static_cast<std::size_t>(width));
    std::memcpy(saturated_to_ + k * v_.saturated.width, solution + v_.saturated.offset,
                sizeof(bool) * static_cast<std::size_t>(v_.saturated.width));
    std::memcpy(dropped_pivots_to_ + k, solution + v_.dropped_pivots, sizeof(std::int32_t));
    std::memcpy(locked_joints_to_ + k, solution + v_.locked_joints, sizeof(std::int32_t));
    std::memcpy(status_to_ + k, solution + v_.status, sizeof(std::uint32_t));
  }

  unsigned status(py::ssize_t k) const { return status_to_[k]; }

  // {qdd, tau_cmd, tau_ctrl, nu, tip_acceleration, (set_acceleration,) (closure_error,) (coupling_torque,) saturated, dropped_pivots,
  // locked_joints, status}: (K, ...) arrays when batched, else 1-D arrays and Python ints.
  py::dict dict() const {
    const auto per_row = [&](const auto& values) -> py::object {
      if (batch_.batched) return values;
      return py::int_(values.at(0));
    };
    py::dict d;
    d["qdd"] = arrays_[0];
    d["tau_cmd"] = arrays_[1];
    d["tau_ctrl"] = arrays_[2];
    d["nu"] = arrays_[3];
    d["tip_acceleration"] = arrays_[4];
    if (v_.set_acceleration.width > 0) d["set_acceleration"] = arrays_[5];
    if (v_.closure_error.width > 0) d["closure_error"] = arrays_[6];
    if (v_.coupling_torque.width > 0) d["coupling_torque"] = arrays_[7];
    d["saturated"] = saturated_;
    d["dropped_pivots"] = per_row(dropped_pivots_);
    d["locked_joints"] = per_row(locked_joints_);
    d["status"] = per_row(status_);
    return d;
  }

 private:
  static constexpr std::size_t kArrays = 8;  // the Scalar members, in write()'s order
  const Variant<Scalar>& v_;
  Batch batch_;
  py::array_t<Scalar> arrays_[kArrays];
  Scalar* to_[kArrays] = {};
  py::array_t<bool> saturated_;
  py::array_t<std::int32_t> dropped_pivots_, locked_joints_;
  py::array_t<std::uint32_t> status_;
  Member members_[kArrays];  // where each of arrays_' values lies in a Solution
  bool* saturated_to_;
  std::int32_t *dropped_pivots_to_, *locked_joints_to_;
  std::uint32_t* status_to_;
};

// Bytes for `count` of a generated struct of `size` bytes (State, Solution, Derivatives): rows of
// doubles, floats, ints and bools, so that operator new's alignment serves each.
std::vector<unsigned char> structs(std::size_t size, std::size_t count = 1) { return std::vector<unsigned char>(size * count); }

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
void solve_in_batch(void (*batch)(int, const Scalar*, Scalar*), py::ssize_t rows, int in_size, int out_size,
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
void flat_rows_in_batch(void (*batch)(int, const Scalar*, Scalar*), py::ssize_t rows, int in_size,
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

// One call's states given as their parts, each read by rows_of: q (nq), qd (nv), the flat drivers
// and beta (constraints).
template <class Scalar>
struct StateRows {
  Rows<Scalar> q, qd, drivers, beta;
  Batch batch() const { return batch_of<Scalar>({&q, &qd, &drivers, &beta}); }
};

template <class Scalar>
StateRows<Scalar> state_rows_of(const py::object& q, const py::object& qd, const py::object& drivers,
                                const py::object& beta, py::ssize_t nq, py::ssize_t nv, py::ssize_t n_drivers,
                                py::ssize_t constraints) {
  return {rows_of<Scalar>(q, "q", nq), rows_of<Scalar>(qd, "qd", nv), rows_of<Scalar>(drivers, "drivers", n_drivers),
          rows_of<Scalar>(beta, "beta", constraints)};
}

// solve_in_batch's `in_row` for states given as their parts: row s's q, qd, drivers and beta, in
// the flat input's order.
template <class Scalar>
auto flat_input_of(const StateRows<Scalar>& in) {
  return [&in](std::size_t s, Scalar* to) {
    const auto k = static_cast<py::ssize_t>(s);
    to = std::copy_n(in.q.row(k), in.q.width, to);
    to = std::copy_n(in.qd.row(k), in.qd.width, to);
    to = std::copy_n(in.drivers.row(k), in.drivers.width, to);
    std::copy_n(in.beta.row(k), in.beta.width, to);
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

// Index of `policy` among a variant's derivative functions. A policy of the scene without one is
// not differentiable (docs/generated-code.md, "Derivatives": the saturating policies clamp, a kink in the solve):
// the ValueError says so, not that the scene lacks the policy.
template <class Scalar>
std::size_t derivative_index(const Variant<Scalar>& v, const std::string& policy) {
  std::string differentiable;
  for (std::size_t k = 0; k < v.derivative_solves.size(); ++k) {
    if (policy == v.derivative_solves[k].policy) return k;
    differentiable += (k ? ", " : "") + std::string(v.derivative_solves[k].policy);
  }
  for (const auto& entry : v.solves)
    if (policy == entry.policy)
      throw py::value_error("policy: '" + policy + "' is a policy of this scene but is not differentiable: it clamps "
                            "torques at their limits, a kink in the solve, so no derivatives are generated for it "
                            "(derivatives of this scene: " + differentiable + ")");
  return policy_index(v.derivative_solves, policy);
}

// derivatives(): the values and the Jacobians of one state or K, split by the columns of (D2):
// d_<y>_dq (rows, nv), d_<y>_dqd (rows, nv), d_<y>_dtau_ff (rows, dof), d_<y>_dbeta (rows,
// constraints), each (K, rows, columns) when batched; y the outputs the scene asks Jacobians of
// (derivative_outputs).
template <class Scalar>
void bind_derivatives(py::module_& m, const Scene& scene, const Variant<Scalar>& v, const std::string& prefix,
                      py::ssize_t n_drivers) {
  const py::ssize_t dof = scene.dof, nq = scene.nq, nv = scene.nv, constraints = scene.constraints;
  py::list policies;
  for (const auto& entry : v.derivative_solves) policies.append(entry.policy);
  m.attr("derivative_policies") = py::tuple(policies);
  m.attr("derivative_columns") = v.derivative_columns;
  m.attr("derivative_flat_out_size") = v.derivative_flat_out_size;  // values a state, derivatives()' flat layout
  // Per output y: its name, its rows and whether its Jacobian is returned (the header's derivative_of_*).
  const std::vector<std::tuple<const char*, py::ssize_t, bool>> kOutputs = {
      {"qdd", dof, v.d_jacobians[0].width > 0}, {"nu", constraints, v.d_jacobians[1].width > 0},
      {"tau_cmd", dof, v.d_jacobians[2].width > 0}};
  py::list returned;
  for (const auto& [name, rows, with_jacobian] : kOutputs)
    if (with_jacobian && rows > 0) returned.append(name);
  m.attr("derivative_outputs") = py::tuple(returned);
  m.def(
      "derivatives",
      [&v, kOutputs, prefix, n_drivers, dof, nq, nv, constraints](const py::object& q, const py::object& qd, const py::object& drivers,
                                                            const py::object& beta, const std::string& policy, unsigned mask) {
        const StateRows<Scalar> in = state_rows_of<Scalar>(q, qd, drivers, beta, nq, nv, n_drivers, constraints);
        const std::size_t index = derivative_index(v, policy);
        const Batch batch = in.batch();
        const py::ssize_t columns = v.derivative_columns;
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
              v.derivative_batch_solves[index].solve, batch.rows, v.flat_in_size, v.derivative_flat_out_size,
              flat_input_of(in),
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
          std::vector<unsigned char> r = structs(v.derivatives_size);
          v.derivative_solves[index].solve(in.q.row(0), in.qd.row(0), in.drivers.row(0), in.beta.row(0), r.data());
          const Scalar* values[3] = {nullptr, nullptr, nullptr};
          const Scalar* jacobians[3] = {nullptr, nullptr, nullptr};
          for (std::size_t o = 0; o < 3; ++o) {
            if (v.d_values[o].width > 0) values[o] = reinterpret_cast<const Scalar*>(r.data() + v.d_values[o].offset);
            if (v.d_jacobians[o].width > 0) jacobians[o] = reinterpret_cast<const Scalar*>(r.data() + v.d_jacobians[o].offset);
          }
          std::uint32_t row_status;
          std::memcpy(&row_status, r.data() + v.d_status, sizeof row_status);
          store(0, values, jacobians, row_status);
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
      py::arg("policy") = v.derivative_solves.at(0).policy, py::arg("raise_on_status") = 0u,
      "The generated derivatives_<policy> (scene key derivatives): arguments as solve(). Returns a dict: qdd, nu, "
      "tau_cmd and, for each y of derivative_outputs, d_y_dq, d_y_dqd (rows, nv), d_y_dtau_ff (rows, dof) and d_y_dbeta (rows, constraints) "
      "(K, rows, columns) when batched: a floating base's first six q columns are its rotation vector in its own "
      "frame and its position (docs/derivation.md, D2); status.");
}

// `<name>(n, in, out, stream, *, policy)`: a CUDA table's kernels (module.cuda) on n states already
// in device memory, in the batch layout (value k of state s at [k * n + s]): in and out device
// addresses (a tensor's data_ptr()), `stream` a cudaStream_t's address (torch.cuda's cuda_stream),
// out holding out_size rows. Queues the launch and returns; a CUDA error raises RuntimeError. The
// PyTorch layer's path for CUDA tensors: an address is not checked, so the layer checks the tensors.
template <class Scalar>
void bind_cuda(py::module_& m, const char* name, const std::vector<typename Variant<Scalar>::CudaSolve>& table,
               const std::string& prefix, int out_size) {
  if (table.empty()) return;
  m.def(
      name,
      [&table, prefix, name](py::ssize_t n, std::uintptr_t in, std::uintptr_t out, std::uintptr_t stream,
                             const std::string& policy) {
        const std::size_t index = policy_index(table, policy);
        if (n < 0 || n > std::numeric_limits<int>::max()) throw py::value_error(prefix + name + ": n = " + std::to_string(n) + " states is not within 0 .. 2^31 - 1");
        if (n > 0 && (in == 0 || out == 0)) throw py::value_error(prefix + name + ": a null device address");
        const char* error = nullptr;
        {
          py::gil_scoped_release release;
          error = table[index].solve(static_cast<int>(n), reinterpret_cast<const Scalar*>(in),
                                     reinterpret_cast<Scalar*>(out), reinterpret_cast<void*>(stream));
        }
        if (error) throw std::runtime_error(prefix + name + " (policy " + policy + "): CUDA: " + error);
      },
      py::arg("n"), py::arg("in_address"), py::arg("out_address"), py::arg("stream"), py::kw_only(),
      py::arg("policy") = table.at(0).policy,
      ("The generated CUDA kernels on n states in device memory, in the batch layout (value k of state s at "
       "[k * n + s]; " + std::to_string(out_size) + " output rows): addresses as ints, queued on the "
       "cudaStream_t `stream`. The PyTorch layer's path for CUDA tensors.").c_str());
}

// outward() and decompose() results of one state or of K (a batched outward()): K States' bytes.
template <class Scalar>
struct StateBatch {
  std::vector<unsigned char> bytes;
  std::size_t size = 0;  // sizeof(State)
  bool batched = false;
  bool decomposed = false;

  std::size_t count() const { return bytes.size() / size; }
  Batch batch() const { return {batched, static_cast<py::ssize_t>(count())}; }
  unsigned char* at(py::ssize_t k) { return bytes.data() + size * static_cast<std::size_t>(batched ? k : 0); }
  const unsigned char* at(py::ssize_t k) const { return bytes.data() + size * static_cast<std::size_t>(batched ? k : 0); }
};

template <class Scalar>
void bind_variant(py::module_& module, const Scene& scene, const Variant<Scalar>& v, const char* doc) {
  using State = StateBatch<Scalar>;
  const py::ssize_t dof = scene.dof, nq = scene.nq, nv = scene.nv, constraints = scene.constraints;
  // The flat input between q, qd and beta: the drivers (the module's flat_in_layout).
  const py::ssize_t n_drivers = v.flat_in_size - nq - nv - constraints;
  py::module_ m = module.def_submodule(v.name, doc);
  const std::string prefix = module.attr("__name__").cast<std::string>() + "." + v.name + ".";

  py::list policies;
  for (const auto& entry : v.solves) policies.append(entry.policy);
  const std::string default_policy = v.solves.at(0).policy;
  m.attr("dof") = dof;
  m.attr("nq") = nq;
  m.attr("nv") = nv;
  m.attr("constraints") = constraints;
  m.attr("drivers_size") = n_drivers;
  m.attr("flat_in_size") = v.flat_in_size;
  m.attr("flat_out_size") = v.flat_out_size;
  m.attr("policies") = py::tuple(policies);
  m.attr("dtype") = py::dtype::of<Scalar>();

  py::class_<State>(m, "State",
                    "outward() (and decompose()) results of one state, or of K states for 2-D q and qd. Opaque: "
                    "made by outward(), completed by decompose(), read by solve_state().")
      .def_property_readonly("batched", [](const State& s) { return s.batched; })
      .def_property_readonly("decomposed", [](const State& s) { return s.decomposed; })
      .def("__len__", [](const State& s) { return s.count(); });

  m.def(
      "outward",
      [&v, nq, nv](const py::object& q, const py::object& qd) {
        const Rows<Scalar> q_rows = rows_of<Scalar>(q, "q", nq), qd_rows = rows_of<Scalar>(qd, "qd", nv);
        const Batch batch = batch_of<Scalar>({&q_rows, &qd_rows});
        State state;
        state.size = v.state_size;
        state.batched = batch.batched;
        state.bytes = structs(v.state_size, static_cast<std::size_t>(batch.rows));
        for_each_row(batch, [&](py::ssize_t k) { v.outward(q_rows.row(k), qd_rows.row(k), state.at(k)); });
        return state;
      },
      py::arg("q"), py::arg("qd"),
      "Outward sweep: everything that depends on q, qd only. q: (nq,) or (K, nq), qd: (nv,) or (K, nv). Returns a State.");

  m.def(
      "decompose",
      [&v, n_drivers](State& state, const py::object& drivers) {
        const Rows<Scalar> d = rows_of<Scalar>(drivers, "drivers", n_drivers);
        if (d.batched && !state.batched)
          throw py::value_error("drivers: 2-D drivers need a batched state (outward() of 2-D q, qd)");
        const Batch batch = batch_of<Scalar>({&d}, state.batch());
        for_each_row(batch, [&](py::ssize_t k) { v.decompose(d.row(k), state.at(k)); });
        state.decomposed = true;
      },
      py::arg("state"), py::arg("drivers") = py::none(),
      "Decomposition over the drivers, in place. drivers: (drivers_size,) or (K, drivers_size), the flat "
      "input after q and qd, without beta (module flat_in_layout); None when drivers_size is 0.");

  m.def(
      "solve_state",
      [&v, prefix, constraints](const State& state, const py::object& beta, const std::string& policy, unsigned mask) {
        const Rows<Scalar> b = rows_of<Scalar>(beta, "beta", constraints);
        if (!state.decomposed) throw py::value_error("state: decompose() has not run on it");
        const auto solve = v.solves[policy_index(v.solves, policy)].solve;
        const Batch batch = batch_of<Scalar>({&b}, state.batched ? state.batch() : Batch{});
        Results<Scalar> results(v, batch);
        std::vector<unsigned char> solution = structs(v.solution_size);
        for_each_row(batch, [&](py::ssize_t k) {
          solve(state.at(k), b.row(k), solution.data());
          results.write(k, solution.data());
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
      [&v, prefix, nq, nv, n_drivers, constraints](const py::object& q, const py::object& qd, const py::object& drivers,
                                                   const py::object& beta, const std::string& policy, unsigned mask) {
        const StateRows<Scalar> in = state_rows_of<Scalar>(q, qd, drivers, beta, nq, nv, n_drivers, constraints);
        const auto solve = v.solves[policy_index(v.solves, policy)].solve;
        const Batch batch = in.batch();
        Results<Scalar> results(v, batch);
        std::vector<unsigned char> state = structs(v.state_size), solution = structs(v.solution_size);
        for_each_row(batch, [&](py::ssize_t k) {
          v.outward(in.q.row(k), in.qd.row(k), state.data());
          v.decompose(in.drivers.row(k), state.data());
          solve(state.data(), in.beta.row(k), solution.data());
          results.write(k, solution.data());
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
      [&v, prefix](const py::object& in, const std::string& policy, unsigned mask) {
        const Rows<Scalar> in_rows = rows_of<Scalar>(in, "in", v.flat_in_size);
        const std::size_t index = policy_index(v.flat_solves, policy);
        const Batch batch = batch_of<Scalar>({&in_rows});
        py::array_t<Scalar> out = array_of<Scalar>(batch, v.flat_out_size);
        Scalar* out_data = out.mutable_data();
        if (batch.batched) {  // the batch entry point
          flat_rows_in_batch<Scalar>(
              v.batch_solves[index].solve, batch.rows, v.flat_in_size, v.flat_out_size,
              [&](std::size_t s, Scalar* to) { std::copy_n(in_rows.row(static_cast<py::ssize_t>(s)), v.flat_in_size, to); },
              out_data);
        } else {
          v.flat_solves[index].solve(in_rows.row(0), out_data);
        }
        raise_on_status(mask, batch, flat_status_of(out_data, v.flat_out_size), prefix + "solve_flat", policy, out);
        return out;
      },
      py::arg("in"), py::kw_only(), py::arg("policy") = default_policy, py::arg("raise_on_status") = 0u,
      "The generated flat entry point: in (flat_in_size,) or (K, flat_in_size) -> out (flat_out_size,) or "
      "(K, flat_out_size), layouts in the module's flat_in_layout and flat_out_layout (status last). K rows go "
      "through the generated solve_<policy>_batch: several states per vector instruction.");

  m.def(
      "solve_batch",
      [&v, prefix, nq, nv, n_drivers, constraints](const py::object& q, const py::object& qd, const py::object& drivers,
                                                   const py::object& beta, const std::string& policy, unsigned mask) {
        const StateRows<Scalar> in = state_rows_of<Scalar>(q, qd, drivers, beta, nq, nv, n_drivers, constraints);
        const std::size_t index = policy_index(v.flat_solves, policy);
        const Batch batch{true, in.batch().rows};
        py::array_t<Scalar> out = array_of<Scalar>(batch, v.flat_out_size);
        Scalar* out_data = out.mutable_data();
        flat_rows_in_batch<Scalar>(v.batch_solves[index].solve, batch.rows, v.flat_in_size, v.flat_out_size,
                                   flat_input_of(in), out_data);
        raise_on_status(mask, batch, flat_status_of(out_data, v.flat_out_size), prefix + "solve_batch", policy, out);
        return out;
      },
      py::arg("q"), py::arg("qd"), py::arg("drivers") = py::none(), py::arg("beta") = py::none(), py::kw_only(),
      py::arg("policy") = default_policy, py::arg("raise_on_status") = 0u,
      "The generated solve_<policy>_batch on K states given as solve()'s arguments, without forming their flat "
      "input first: q, qd, drivers, beta as solve() takes them (at least one 2-D, or K = 1) -> out (K, "
      "flat_out_size), solve_flat()'s layout. What the PyTorch layer's forward calls.");
}

// Submodule f64 or f32 of a scalar variant: its solves, derivatives and CUDA kernels; whether it
// has CUDA kernels.
template <class Scalar>
bool bind_scalar(py::module_& m, const Scene& scene, const Variant<Scalar>& v, const char* doc, py::list& scalars) {
  bind_variant(m, scene, v, doc);
  scalars.append(v.name);
  py::module_ sub = m.attr(v.name);
  const std::string prefix = m.attr("__name__").cast<std::string>() + "." + v.name + ".";
  if (!v.derivative_solves.empty())
    bind_derivatives(sub, scene, v, prefix, v.flat_in_size - scene.nq - scene.nv - scene.constraints);
  bind_cuda<Scalar>(sub, "_solve_cuda", v.cuda_solves, prefix, v.flat_out_size);
  bind_cuda<Scalar>(sub, "_derivatives_cuda", v.derivative_cuda_solves, prefix, v.derivative_flat_out_size);
  if (v.cuda_solves.empty()) return false;
  // The kernels' statuses (read back to the host) against raise_on_status, as the CPU calls raise it.
  sub.def(
      "_raise_on_status",
      [prefix](const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& status,
               const std::string& function, const std::string& policy, unsigned mask) {
        const std::int64_t* words = status.data();
        raise_on_status(mask, Batch{true, status.size()}, [words](py::ssize_t k) { return static_cast<unsigned>(words[k]); },
                        prefix + function, policy, py::none());
      },
      py::arg("status"), py::arg("function"), py::arg("policy"), py::arg("mask"),
      "SolverStatusError for the first of K status words (the CUDA kernels') with a flag of mask, as solve_batch "
      "raises it (result None).");
  return true;
}

// The module's attributes and submodules (PYBIND11_MODULE's body, for the scene described).
void bind_module(py::module_& m, const Scene& scene) {
  const std::string name = scene.module_name;
  m.doc() = "The sweepgen-generated solver " + std::string(scene.scene_name) +
            " (README, \"Python\"): submodules f64 and/or f32 with outward, decompose, solve_state, solve, "
            "solve_flat and solve_batch. Flat input: [" + scene.flat_in_layout + "]; the drivers are the part after q and qd, "
            "without beta.";
  m.attr("dof") = scene.dof;
  m.attr("nq") = scene.nq;
  m.attr("nv") = scene.nv;
  m.attr("constraints") = scene.constraints;
  m.attr("checks_inputs") = scene.checks_inputs;
  m.attr("flat_in_layout") = scene.flat_in_layout;
  m.attr("flat_out_layout") = scene.flat_out_layout;

  status_flags = flags_of(scene);
  py::dict flags;
  flags["ok"] = scene.status_ok;
  for (const Flag& flag : status_flags) flags[flag.name] = flag.value;
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
  bool cuda = false;
  if (scene.f64) cuda = bind_scalar(m, scene, *scene.f64, "double arithmetic", scalars) || cuda;
  if (scene.f32) cuda = bind_scalar(m, scene, *scene.f32, "float arithmetic", scalars) || cuda;
  m.attr("scalars") = py::tuple(scalars);
  // Whether the module has CUDA kernels (built with its solver's CUDA library: README, "PyTorch").
  m.attr("cuda") = cuda;

  // <module>.torch: the PyTorch layer (python/torch_layer.py), run on first use (a module-level
  // __getattr__, PEP 562), so that importing the module never imports torch.
  const std::string torch_layer = scene.torch_layer;
  m.def("__getattr__", [name, torch_layer](const std::string& attribute) -> py::object {
    if (attribute != "torch") throw py::attribute_error("module '" + name + "' has no attribute '" + attribute + "'");
    py::module_ self = py::module_::import(name.c_str());
    py::dict scope;
    scope["__name__"] = name + ".torch";
    scope["__builtins__"] = py::module_::import("builtins");
    try {
      py::exec(torch_layer, scope);
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

}  // namespace

// PYBIND11_MODULE's initialisation for a module whose PyInit_<name> is in its own source.
PyObject* make_module(const Scene& scene) noexcept {
  PYBIND11_CHECK_PYTHON_VERSION
  PYBIND11_ENSURE_INTERNALS_READY
  static py::module_::module_def definition;  // one module per shared object
  auto m = py::module_::create_extension_module(scene.module_name, nullptr, &definition);
  try {
    bind_module(m, scene);
    return m.ptr();
  }
  PYBIND11_CATCH_INIT_EXCEPTIONS
  return nullptr;  // the Python error is set (pybind11 3's catch clauses do not return)
}

}  // namespace sweepgen_python
