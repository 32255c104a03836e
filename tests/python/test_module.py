"""The Python modules of the bundled scenes (python/module.cpp, README "Python") against `sweepgen solve`.

Run by ctest (tests/python/CMakeLists.txt) with the interpreter the modules were built for and
  PYTHONPATH              the directory of the modules
  SWEEPGEN_EXECUTABLE     the generator (its `solve` runs ReferenceSolver<double>, the oracle)
  SWEEPGEN_PROBLEMS       python_test_problems (problems.cpp): random problems of a scene with their
                          flat input, kappa and `sweepgen solve` line
  SWEEPGEN_PYTHON_SCENES  module=scene.yaml pairs, comma-separated

Per module and scalar (f64, f32):
  - constants: sizes, policies and Status flags equal the scene's (python_test_problems prints
    them from the scene and sweepgen's solver/state.hpp);
  - every policy's single solve() against the oracle on STATES random problems, every output
    (qdd, tau_cmd, tau_ctrl, nu, tip_acceleration, status flags, saturated joints), within the
    bounds derived at FACTORS;
  - batched solve(), solve_flat() single and batched, solve_batch(), and a batched or broadcast
    outward/decompose/solve_state equal the single solve() bit for bit (one compiled code path);
  - outward + decompose once, solve_state with a first beta, then with the problem's beta, equals
    a full solve with the latter bit for bit;
  - bad shapes, dtypes, policies and call order raise ValueError naming the argument;
  - raise_on_status raises SolverStatusError carrying the status, row, policy and result.
"""

import importlib
import json
import os
import subprocess
import sys
import unittest

import numpy as np

STATES = 64
SEED = 2024

# The error measure of tests/generated (oracle/relative_error.hpp): ||a - b||_inf / max(1, ||b||_inf),
# per output vector, judged against factor * eps * kappa with kappa = max(1, cond_s(E^A_cstr,0),
# 1 / min rho_i) of the state (docs/stability.md; python_test_problems computes it with the
# binary128 referee), only inside each scalar's domain of validity (tests/support/rounding_bound.hpp:
# kDoubleMaxKappa, kFloatMaxKappa). States beyond it are counted, their share asserted.
#   f64 vs `sweepgen solve` (ReferenceSolver<double>): the generated code is the reference's traced
#     operations, differing by constant folding and the compiler's order only, so by a few roundings
#     amplified like any rounding: 40 eps kappa, the factor tests/support/generated_check.cpp derives
#     for the same comparison (kSameOperations; measured there 1.1). Ceiling inside kappa <= 1e8:
#     8.9e-7. The share beyond 1e8 is at most 5%, as there (measured 2.3% for Panda Nc = 6).
#   f32 vs the same double oracle: float's own error against the exact answer, <= 100 eps_f kappa
#     (generated_check's float accuracy factor), plus the double oracle's, <= 100 eps_d kappa (the
#     stability suite's factor); judged for kappa <= 1e3 (ceiling 1.2e-2). Six random directions
#     on a 7-joint arm are nearly always beyond 1e3 (tests/generated: Panda Nc = 6, 1000 of 1000),
#     so there the share is not bounded; the unit-axis directions (python_test_problems `axes`)
#     are mostly within it (25% allowed; on the Panda 3 of the 64 here), and Nc = 0 has no
#     directions (5% allowed; tests/generated: 0 of 1000 beyond). 64 states, so that a 5% share
#     allows 3 (16 allowed none, where the floating mobile Panda's measured 1.15% beyond 1e8 in
#     tests/generated put 1 of 16 there; here 2 of 64).
EPS = {"f64": float(np.finfo(np.float64).eps), "f32": float(np.finfo(np.float32).eps)}
MAX_KAPPA = {"f64": 1e8, "f32": 1e3}
FACTORS = {"f64": 40 * EPS["f64"], "f32": 100 * EPS["f32"] + 100 * EPS["f64"]}


def max_share_beyond(scalar, directions, constraints):
    if scalar == "f32" and directions == "random" and constraints > 0:
        return 1.0
    return 0.25 if scalar == "f32" and directions == "axes" else 0.05


# Module key, `sweepgen solve` key, and the oracle's vectors whose size also scales the error: the
# tip acceleration sums the joint terms S_i qdd_i carried to the tip (S5; angular parts |qdd_i|,
# linear parts |qdd_i| times the distance to the tip, under 1.2 m on the Panda), which cancel
# where the constraint holds the tip still while the arm moves fast (measured: |qdd| 131 for
# |Xdd_tip| 2.5, error 62 eps kappa relative to Xdd_tip, 1.2 relative to qdd).
OUTPUTS = [("qdd", "qdd", ()), ("tau_cmd", "tau_cmd", ()), ("tau_ctrl", "tau_ctrl", ()), ("nu", "nu", ()),
           ("tip_acceleration", "xdd_tip", ("qdd",))]
CLI_FLAGS = ["constraint_rank_deficient", "saturated", "not_finite"]  # what `sweepgen solve` prints


def relative_error(a, b, also=()):
    """||a - b||_inf / max(1, ||b||_inf, ||c||_inf for c in also): `also`, the terms b is the sum of
    (where they cancel, rounding is relative to them, not to b; report::joint_relative_error)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.shape != b.shape or not np.all(np.isfinite(a)):
        return np.inf
    if a.size == 0:
        return 0.0
    scale = max([1.0, float(np.max(np.abs(b)))] + [float(np.max(np.abs(c))) for c in also])
    return float(np.max(np.abs(a - b)) / scale)


def results_equal(a, b):
    """Two solve results bit for bit: same keys, same values, dtypes and shapes."""
    if a.keys() != b.keys():
        return False
    return all(np.array_equal(np.asarray(a[k]), np.asarray(b[k])) and np.asarray(a[k]).dtype == np.asarray(b[k]).dtype
               for k in a)


def row(result, k):
    """Row k of a batched result, as an unbatched one (ints for the per-row counts)."""
    return {key: (int(value[k]) if value.ndim == 1 else value[k]) for key, value in result.items()}


class ProblemSet:
    """Random problems of a scene (constraint directions random or the unit axes) and the oracle's
    answers, computed once per test class."""

    def __init__(self, scene_path, directions):
        self.directions = directions
        extra = ["axes"] if directions == "axes" else []
        lines = subprocess.run([os.environ["SWEEPGEN_PROBLEMS"], scene_path, str(STATES), str(SEED), *extra],
                               check=True, capture_output=True, text=True).stdout.splitlines()
        self.info = json.loads(lines[0])
        problems = [json.loads(line) for line in lines[1:]]
        self.flat = np.array([p["in"] for p in problems], dtype=np.float64)
        self.kappa = np.array([p["kappa"] for p in problems])
        self.dof, self.nc, self.sets = self.info["dof"], self.info["constraints"], self.info["sets"]
        self.nq = self.info["nq"]  # values of q: dof, or a floating base's rotation (9) and the joints' positions
        self.nv = self.info["nv"]  # values of qd: dof, less the coupled <mimic> joints
        self.oracle = {}  # policy -> one `sweepgen solve` answer per problem
        cli_input = "".join(json.dumps(dict(p["cli"], policy=policy)) + "\n"
                            for policy in self.info["policies"] for p in problems)
        answers = subprocess.run([os.environ["SWEEPGEN_EXECUTABLE"], "solve", "--urdf", self.info["urdf"],
                                  *self.info["cli_args"], "--input", "-"],
                                 input=cli_input, check=True, capture_output=True, text=True).stdout.splitlines()
        for i, policy in enumerate(self.info["policies"]):
            self.oracle[policy] = [json.loads(a) for a in answers[i * len(problems):(i + 1) * len(problems)]]

    def split(self, flat):
        """q, qd, drivers, beta of flat inputs (1-D or 2-D): the module's flat_in_layout."""
        nv, nq, nc = self.nv, self.nq, self.nc
        return (flat[..., :nq], flat[..., nq:nq + nv], flat[..., nq + nv:flat.shape[-1] - nc],
                flat[..., flat.shape[-1] - nc:])


class ModuleTest:
    """Tests of one module; subclassed per scene below (STEM, SCENE)."""

    STEM = SCENE = None

    @classmethod
    def setUpClass(cls):
        cls.m = importlib.import_module(cls.STEM)
        cls.data = ProblemSet(cls.SCENE, "random")
        cls.problem_sets = [cls.data] + ([ProblemSet(cls.SCENE, "axes")] if cls.data.nc > 0 else [])

    def variants(self):
        return [(name, getattr(self.m, name)) for name in self.m.scalars]

    def test_constants(self):
        info, m = self.data.info, self.m
        self.assertEqual(m.scalars, ("f64", "f32"))  # both bundled scenes emit double and float
        self.assertEqual((m.dof, m.nq, m.nv, m.constraints, m.checks_inputs),
                         (info["dof"], info["nq"], info["nv"], info["constraints"], True))
        for flag, value in info["status"].items():
            self.assertEqual(int(getattr(m.Status, flag)), value, flag)
        q_size = "nq" if info["nq"] != info["dof"] else "dof"  # a floating base's q (world_R_base first)
        qd_size = "nv" if info["couplings"] > 0 else "dof"  # no entry for a coupled <mimic> joint
        self.assertTrue(m.flat_in_layout.startswith(f"q ({q_size}), qd ({qd_size}), "), m.flat_in_layout)
        self.assertTrue(m.flat_out_layout.startswith("qdd (dof), tau_cmd (dof), tau_ctrl (dof), "), m.flat_out_layout)
        for name, v in self.variants():
            self.assertEqual(v.flat_in_size, info["flat_in_size"], name)
            closure = 12 * info["loop_sets"]  # each set between two links: pose error, v_rel
            self.assertEqual(v.flat_out_size, 3 * info["dof"] + info["constraints"] + info["couplings"] + 6 +
                             6 * info["sets"] + closure + 1, name)
            self.assertEqual(v.drivers_size, info["flat_in_size"] - info["nq"] - info["nv"] - info["constraints"], name)
            self.assertEqual(list(v.policies), info["policies"], name)
            self.assertEqual(v.dtype, np.dtype(np.float64 if name == "f64" else np.float32), name)

    def test_single_solves_match_sweepgen_solve(self):
        for d in self.problem_sets:
            for name, v in self.variants():
                self.check_against_oracle(d, name, v)

    def check_against_oracle(self, d, name, v):
        """Every policy's single solve() of each problem of `d` against `sweepgen solve`."""
        what = f"{self.STEM}.{name}" + (f", {d.directions} directions" if d.nc > 0 else "")
        beyond = 0
        worst = 0.0  # max error / (eps kappa) over the judged outputs
        for k in range(STATES):
            inside = d.kappa[k] <= MAX_KAPPA[name]
            beyond += not inside
            q, qd, drivers, beta = d.split(d.flat[k])
            for policy in v.policies:
                r = v.solve(q, qd, drivers, beta, policy=policy)
                answer = d.oracle[policy][k]
                where = f"{what}: {policy} state {k} (kappa {d.kappa[k]:.3g})"
                for key, _, _ in OUTPUTS:
                    self.assertTrue(np.all(np.isfinite(r[key])), where + " " + key)
                if not inside:
                    continue
                flags = {f for f in CLI_FLAGS if r["status"] & int(getattr(self.m.Status, f))}
                oracle_flags = set() if answer["status"] == "ok" else set(answer["status"].split(","))
                # Inside the domain no pivot is dropped and no joint locked: a kept pivot has
                # d_k / E_kk >= 1 / (4 cond_s) (equilibration leaves E_kk in [1, 4)), a kept joint
                # rho_i > 1000 eps, and 4 kappa * 1000 eps < 1 there for both scalars; so flags and
                # results are compared in full.
                self.assertEqual(flags, oracle_flags, where)
                self.assertEqual((r["dropped_pivots"], r["locked_joints"]), (0, 0), where)
                saturated = [j for j, s in zip(d.info["joints"], r["saturated"]) if s]
                self.assertEqual(saturated, answer["saturated_joints"], where)
                outputs = OUTPUTS + ([("set_acceleration", "xdd_links", ("qdd",))] if d.sets else [])
                outputs += [("closure_error", "closure_error", ())] if "closure_error" in answer else []
                outputs += [("coupling_torque", "coupling_torque", ())] if "coupling_torque" in answer else []
                for key, cli_key, terms in outputs:
                    # xdd_links: each set's link acceleration by set, in the scene's set order; closure_error:
                    # each set between two links' pose error and relative velocity, in that order.
                    if cli_key == "xdd_links":
                        expected = np.concatenate(list(answer[cli_key].values()))
                    elif cli_key == "closure_error":
                        expected = np.concatenate([e["pose_error"] + e["relative_velocity"] for e in answer[cli_key].values()])
                    elif cli_key == "coupling_torque":  # by coupled joint, in joint order
                        expected = np.array(list(answer[cli_key].values()))
                    else:
                        expected = answer[cli_key]
                    error = relative_error(r[key], expected, [answer[t] for t in terms])
                    worst = max(worst, error / (EPS[name] * max(1.0, d.kappa[k])))
                    self.assertLessEqual(error, FACTORS[name] * max(1.0, d.kappa[k]), f"{where} {key}")
        share = max_share_beyond(name, d.directions, d.nc)
        print(f"[rounding] {what} vs sweepgen solve: max error/(eps kappa) {worst:.3g} "
              f"(allowed {FACTORS[name] / EPS[name]:.3g})", file=sys.stderr)
        print(f"[skips] {what}: {beyond} of {STATES} states with kappa > {MAX_KAPPA[name]:.0e}, "
              f"at most {100 * share:.0f}% allowed", file=sys.stderr)
        self.assertLessEqual(beyond, share * STATES, what)

    def test_batched_and_flat_calls_equal_single_solves(self):
        d = self.data
        for name, v in self.variants():
            flat = d.flat.astype(v.dtype)
            q, qd, drivers, beta = d.split(flat)
            for policy in v.policies:
                batched = v.solve(q, qd, drivers, beta, policy=policy)
                flat_batched = v.solve_flat(flat, policy=policy)
                self.assertTrue(np.array_equal(v.solve_batch(q, qd, drivers, beta, policy=policy), flat_batched))
                self.assertEqual(batched["qdd"].shape, (STATES, d.dof))
                self.assertEqual(batched["status"].shape, (STATES,))
                self.assertEqual(flat_batched.shape, (STATES, v.flat_out_size))
                state = v.outward(q, qd)
                self.assertTrue(state.batched)
                self.assertEqual(len(state), STATES)
                v.decompose(state, drivers)
                self.assertTrue(results_equal(v.solve_state(state, beta, policy=policy), batched), policy)
                for k in range(STATES):
                    where = f"{name} {policy} row {k}"
                    single = v.solve(q[k], qd[k], drivers[k], beta[k], policy=policy)
                    self.assertTrue(results_equal(row(batched, k), single), where)
                    out = v.solve_flat(flat[k], policy=policy)
                    self.assertTrue(np.array_equal(out, flat_batched[k]), where)
                    expected = np.concatenate([single["qdd"], single["tau_cmd"], single["tau_ctrl"], single["nu"],
                                               single.get("coupling_torque", []), single["tip_acceleration"],
                                               single.get("set_acceleration", []), single.get("closure_error", []),
                                               [single["status"]]]).astype(v.dtype)
                    self.assertTrue(np.array_equal(out, expected), where)

    def test_resolve_with_new_beta_equals_full_solve(self):
        d = self.data
        rng = np.random.default_rng(SEED)
        for name, v in self.variants():
            flat = d.flat.astype(v.dtype)
            q, qd, drivers, beta = d.split(flat)
            first_beta = rng.uniform(-1, 1, beta.shape).astype(v.dtype)
            for k in range(STATES):
                state = v.outward(q[k], qd[k])
                self.assertFalse(state.decomposed)
                v.decompose(state, drivers[k])
                for policy in v.policies:
                    v.solve_state(state, first_beta[k], policy=policy)
                    again = v.solve_state(state, beta[k], policy=policy)
                    self.assertTrue(results_equal(again, v.solve(q[k], qd[k], drivers[k], beta[k], policy=policy)),
                                    f"{name} {policy} state {k}")
            # One state, every row of setpoints: the setpoint sweep.
            state = v.outward(q[0], qd[0])
            v.decompose(state, drivers[0])
            swept = v.solve_state(state, beta)
            for k in range(STATES):
                self.assertTrue(results_equal(row(swept, k), v.solve(q[0], qd[0], drivers[0], beta[k])), f"{name} {k}")

    def assertValueError(self, pattern, call, *args, **kwargs):
        with self.assertRaisesRegex(ValueError, pattern):
            call(*args, **kwargs)

    def test_bad_arguments_raise_value_errors(self):
        d = self.data
        n, nq = d.nv, d.nq
        for name, v in self.variants():
            q, qd, drivers, beta = d.split(d.flat[0])
            Q, QD, D, B = d.split(d.flat)
            expected_q = rf"q: expected shape \({nq},\) or \(K, {nq}\), got "
            self.assertValueError(expected_q + rf"\({nq - 1},\)", v.solve, q[:-1], qd, drivers, beta)
            self.assertValueError(expected_q + rf"\(1, 2, {nq}\)", v.solve, np.stack([q, q])[None], qd, drivers,
                                  beta)
            self.assertValueError(rf"qd: 3 rows, but q has {STATES}", v.solve, Q, QD[:3], D, B)
            self.assertValueError("q: expected real numbers, got dtype complex128", v.solve, q + 0j, qd, drivers, beta)
            self.assertValueError("qd: expected real numbers, got dtype <U", v.solve, q, ["a"] * n, drivers, beta)
            self.assertValueError("drivers: expected shape", v.solve, q, qd, drivers[:-1], beta)
            self.assertValueError("policy: 'sideways' is not a policy of this scene", v.solve, q, qd, drivers, beta,
                                  policy="sideways")
            self.assertValueError(rf"in: expected shape \({v.flat_in_size},\)", v.solve_flat, d.flat[0][:-1])
            if d.nc > 0:
                self.assertValueError("beta: required", v.solve, q, qd, drivers)
                self.assertValueError(rf"beta: expected shape \({d.nc},\)", v.solve, q, qd, drivers, beta[:-1])
            state = v.outward(q, qd)
            self.assertValueError("state: decompose\\(\\) has not run on it", v.solve_state, state, beta)
            self.assertValueError("drivers: 2-D drivers need a batched state", v.decompose, state, D)
            batched = v.outward(Q, QD)
            self.assertValueError(f"drivers: 2 rows, but the state has {STATES}", v.decompose, batched, D[:2])

    def test_status_raises_solver_status_error(self):
        d = self.data
        m = self.m
        for name, v in self.variants():
            flat = d.flat.astype(v.dtype)
            q, qd, drivers, beta = d.split(flat)
            bad_q = q.copy()
            bad_q[3, 2], bad_q[5, 0] = np.nan, np.inf  # rows 3 and 5 are not finite
            plain = v.solve(bad_q, qd, drivers, beta)
            self.assertEqual([bool(s & m.Status.not_finite) for s in plain["status"]],
                             [k in (3, 5) for k in range(STATES)])
            with self.assertRaises(m.SolverStatusError) as raised:
                v.solve(bad_q, qd, drivers, beta, policy=v.policies[-1], raise_on_status=m.Status.not_finite)
            e = raised.exception
            self.assertIsInstance(e, RuntimeError)
            self.assertTrue(e.status & m.Status.not_finite)
            self.assertEqual((e.index, e.policy), (3, v.policies[-1]))  # the first flagged row
            self.assertEqual(e.result["status"][3], e.status)
            self.assertRegex(str(e), rf"^{self.STEM}\.{name}\.solve \(policy {v.policies[-1]}\): status {e.status} "
                                     rf"\([a-z_|]*not_finite[a-z_|]*\) at row 3 \(2 of {STATES} rows flagged\)")
            with self.assertRaises(m.SolverStatusError) as raised:
                v.solve(bad_q[3], qd[3], drivers[3], beta[3], raise_on_status=m.Status.not_finite)
            self.assertIsNone(raised.exception.index)
            with self.assertRaises(m.SolverStatusError) as raised:
                v.solve_flat(np.concatenate([bad_q[3], flat[3, d.nq:]]), raise_on_status=m.Status.not_finite)
            self.assertTrue(raised.exception.status & m.Status.not_finite)
            # A mask without the raised flags does not raise (the original policy saturates nothing).
            v.solve(bad_q, qd, drivers, beta, policy="original", raise_on_status=m.Status.saturated)
            if d.info["run_time_directions"] > 0:
                zero_alpha = drivers[0].copy()
                # the run-time directions end the drivers (flat_in_layout)
                alpha_0 = drivers.shape[-1] - 6 * d.info["run_time_directions"]
                zero_alpha[alpha_0:alpha_0 + 6] = 0
                with self.assertRaises(m.SolverStatusError) as raised:
                    v.solve(q[0], qd[0], zero_alpha, beta[0], raise_on_status=m.Status.constraint_rank_deficient)
                self.assertEqual(raised.exception.result["dropped_pivots"], 1)


class DerivativeModuleTest:
    """derivatives() of a module whose scene has derivatives: true (docs/generated-code.md, "Derivatives"); subclassed per
    scene below (STEM, SCENE).
      - batched calls return (K, rows, columns) blocks equal to single calls bit for bit;
      - the values qdd, nu, tau_cmd against solve() on the same state: the same traced operations in
        another function, so within the 40 eps kappa of the module test above;
      - the qd, tau_ff and beta columns against central differences of solve() with step 1: at fixed q
        and pivot decisions the solve is affine in tau_ff and beta and quadratic in qd (every velocity
        term is a product of two velocities), so the central difference has no truncation error, only
        the rounding of the two solves, 2 x 40 eps kappa relative to their scale over 2 x 1; the q
        columns are the same trace's (tests/test_generated_derivatives.cpp checks all of them)."""

    STEM = SCENE = None

    @classmethod
    def setUpClass(cls):
        cls.m = importlib.import_module(cls.STEM)
        cls.data = ProblemSet(cls.SCENE, "random")

    def test_derivatives(self):
        d, v = self.data, self.m.f64
        n, nc = d.dof, d.nc
        self.assertEqual(v.derivative_columns, 3 * n + nc)
        q, qd, drivers, beta = d.split(d.flat)
        judged = d.kappa <= MAX_KAPPA["f64"]
        for policy in v.derivative_policies:
            batched = v.derivatives(q, qd, drivers, beta, policy=policy)
            # The Jacobians the scene lists (scene key derivatives) and no others.
            rows = {"qdd": n, "nu": nc, "tau_cmd": n}
            for key in ("qdd", "nu", "tau_cmd"):
                self.assertEqual(f"d_{key}_dq" in batched, key in v.derivative_outputs, key)
            for key in v.derivative_outputs:
                self.assertEqual(batched[f"d_{key}_dq"].shape, (STATES, rows[key], n))
                self.assertEqual(batched[f"d_{key}_dbeta"].shape, (STATES, rows[key], nc))
            tau_0 = 0  # tau_ff leads the drivers (the scene's one torque driver)
            for k in range(STATES):
                where = f"{policy} row {k}"
                single = v.derivatives(q[k], qd[k], drivers[k], beta[k], policy=policy)
                self.assertTrue(results_equal(row(batched, k), single), where)
                if not judged[k]:
                    continue
                bound = FACTORS["f64"] * max(1.0, d.kappa[k])
                solved = v.solve(q[k], qd[k], drivers[k], beta[k], policy=policy)
                for key in ("qdd", "nu", "tau_cmd"):
                    self.assertLessEqual(relative_error(single[key], solved[key]), bound, f"{where} {key}")
                for block, width, offset, index in (("dqd", n, 0, 0), ("dtau_ff", n, tau_0, 1), ("dbeta", nc, 0, 2)):
                    for j in range(width):
                        plus = [qd[k].copy(), drivers[k].copy(), beta[k].copy()]
                        minus = [qd[k].copy(), drivers[k].copy(), beta[k].copy()]
                        plus[index][offset + j] += 1.0
                        minus[index][offset + j] -= 1.0
                        up = v.solve(q[k], plus[0], plus[1], plus[2], policy=policy)
                        down = v.solve(q[k], minus[0], minus[1], minus[2], policy=policy)
                        for key in v.derivative_outputs:
                            difference = (up[key] - down[key]) / 2
                            scale = max(1.0, float(np.max(np.abs(up[key]), initial=0)),
                                        float(np.max(np.abs(down[key]), initial=0)))
                            error = float(np.max(np.abs(single[f"d_{key}_{block}"][:, j] - difference), initial=0)) / scale
                            self.assertLessEqual(error, 2 * bound, f"{where} d_{key}_{block} column {j}")
        print(f"[derivatives] {self.STEM}: {int(judged.sum())} of {STATES} states judged (kappa <= 1e8)", file=sys.stderr)
        self.assertGreaterEqual(judged.sum(), 0.75 * STATES)  # six random directions: see tests/test_solve_derivatives.cpp

    def test_a_policy_without_derivatives_says_why(self):
        """A saturating policy of the scene has no derivatives (a kink where it clamps): derivatives()
        says it is not differentiable, not that the scene lacks it; a name the scene lacks is that."""
        d, v = self.data, self.m.f64
        q, qd, drivers, beta = (a[0] for a in d.split(d.flat))
        without = [p for p in v.policies if p not in v.derivative_policies]
        self.assertTrue(without, f"{self.STEM}: the scene needs a policy without derivatives for this test")
        for policy in without:
            with self.assertRaisesRegex(ValueError, f"'{policy}' is a policy of this scene but is not differentiable"):
                v.derivatives(q, qd, drivers, beta, policy=policy)
        with self.assertRaisesRegex(ValueError, "'saturate_later' is not a policy of this scene"):
            v.derivatives(q, qd, drivers, beta, policy="saturate_later")


def load_tests(loader, tests, pattern):
    suite = unittest.TestSuite()
    for pair in os.environ["SWEEPGEN_PYTHON_SCENES"].split(","):
        stem, scene = pair.split("=", 1)
        case = type(f"Module_{stem}", (ModuleTest, unittest.TestCase), {"STEM": stem, "SCENE": scene})
        suite.addTests(loader.loadTestsFromTestCase(case))
    for pair in filter(None, os.environ.get("SWEEPGEN_PYTHON_DERIVATIVE_SCENES", "").split(",")):
        stem, scene = pair.split("=", 1)
        case = type(f"Derivatives_{stem}", (DerivativeModuleTest, unittest.TestCase), {"STEM": stem, "SCENE": scene})
        suite.addTests(loader.loadTestsFromTestCase(case))
    return suite


if __name__ == "__main__":
    unittest.main(verbosity=2)
