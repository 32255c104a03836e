"""Per-call overhead of a generated solver's Python module (README "Python"), against its own C++ loop.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--module panda_nc6] [--states 20000]

(`cmake --build build --target bench_python` runs it with the interpreter and module directory the
build found.) Prints, per scalar of the module, the wall time per state of
  - single calls from Python: solve() (the structured results, a dict of arrays), solve_flat(),
    solve_state() (the re-solve of a decomposed state);
  - batched calls over K states: solve_flat(), solve(), and solve_state() of one state over K
    setpoint rows, each one C++ loop without the GIL; solve_flat's per-state time is the C++
    flat call itself plus copying its output;
and the overhead of a single call: its time minus the batched per-state time of the same path.
Each figure is the best of --repeat runs (the least disturbed one on a shared machine).
"""

import argparse
import importlib
import time

import numpy as np


def random_inputs(v, states, rng):
    """(K, flat_in_size) flat inputs: q in [-1, 1], qd in [-2, 2], drivers in [-5, 5] with unit
    constraint directions (the drivers' last 6 * constraints values), beta in [-3, 3]."""
    n, nc = v.dof, v.constraints
    flat = np.empty((states, v.flat_in_size))
    flat[:, :n] = rng.uniform(-1, 1, (states, n))
    flat[:, n:2 * n] = rng.uniform(-2, 2, (states, n))
    drivers = rng.uniform(-5, 5, (states, v.drivers_size))
    if nc > 0:
        alpha = rng.uniform(-1, 1, (states, nc, 6))
        alpha /= np.linalg.norm(alpha, axis=2, keepdims=True)
        drivers[:, v.drivers_size - 6 * nc:] = alpha.reshape(states, 6 * nc)
    flat[:, 2 * n:v.flat_in_size - nc] = drivers
    flat[:, v.flat_in_size - nc:] = rng.uniform(-3, 3, (states, nc))
    return flat.astype(v.dtype)


def best_time(call, repeat):
    """The smallest wall time of `repeat` runs of call(), in s."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def per_call(calls, repeat):
    """Best wall time per call of a list of single calls, in µs."""
    def run():
        for call in calls:
            call()
    return best_time(run, repeat) / len(calls) * 1e6


def measure(module_name, v, states, singles, repeat, rng):
    flat = random_inputs(v, states, rng)
    n, nc = v.dof, v.constraints
    q, qd = flat[:, :n], flat[:, n:2 * n]
    drivers, beta = flat[:, 2 * n:v.flat_in_size - nc], flat[:, v.flat_in_size - nc:]
    state = v.outward(q[0], qd[0])
    v.decompose(state, drivers[0])
    k = range(singles)
    single = {
        "solve": per_call([lambda i=i: v.solve(q[i], qd[i], drivers[i], beta[i]) for i in k], repeat),
        "solve_flat": per_call([lambda i=i: v.solve_flat(flat[i]) for i in k], repeat),
        "solve_state": per_call([lambda i=i: v.solve_state(state, beta[i]) for i in k], repeat),
    }
    batched = {
        "solve": best_time(lambda: v.solve(q, qd, drivers, beta), repeat) / states * 1e6,
        "solve_flat": best_time(lambda: v.solve_flat(flat), repeat) / states * 1e6,
        "solve_state": best_time(lambda: v.solve_state(state, beta), repeat) / states * 1e6,
    }
    print(f"{module_name}.{v.__name__.split('.')[-1]} (policy {v.policies[0]}; {singles} single calls, "
          f"batches of {states}):")
    print(f"  {'path':<12} {'single µs':>10} {'batched µs/state':>17} {'overhead µs':>12} {'batched states/s':>17}")
    for path in single:
        print(f"  {path:<12} {single[path]:>10.2f} {batched[path]:>17.3f} {single[path] - batched[path]:>12.2f} "
              f"{1e6 / batched[path]:>17,.0f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--module", default="panda_nc6")
    parser.add_argument("--states", type=int, default=20000, help="rows per batched call")
    parser.add_argument("--singles", type=int, default=2000, help="single calls per timed run")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs; the best counts")
    args = parser.parse_args()
    module = importlib.import_module(args.module)
    rng = np.random.default_rng(1)
    for scalar in module.scalars:
        measure(args.module, getattr(module, scalar), args.states, args.singles, args.repeat, rng)


if __name__ == "__main__":
    main()
