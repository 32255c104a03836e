"""The PyTorch layer of a scene module (README "PyTorch") against the NumPy module's own calls.

    PYTHONPATH=build/python /usr/bin/python3 bench/torch_overhead.py [--module panda_lean_nc6_fixed_derivatives] [--device cuda]

(`cmake --build build --target bench_torch` runs it with the interpreter and module directory the
build found.) For batches of 1, 64 and 4 096 states of the module's f64 variant, the wall time per
call and the states per second of
  - forward: `<module>.torch.solve` without a gradient, against the module's `solve_flat` on the
    same flat rows (both through the generated batch entry point);
  - forward + backward: `torch.solve` with q, qd, the torque drivers and beta requiring grad and
    `backward()` of a weighted sum of qdd, against the module's `derivatives()` (the values and
    Jacobians the backward's products are made of);
and the torch layer's own time per call, the difference. Each figure is the best of --repeat runs
(the least disturbed one on a shared machine); the layer runs with torch's threads as set
(torch.get_num_threads(), printed). --device cuda: the layer on CUDA tensors (a module built with
its solver's CUDA library: tests/python/cuda/run.sh), each call waited for (torch.cuda.synchronize),
also at 65 536 and 1 048 576 states, against the same NumPy calls on the CPU.
"""

import argparse
import importlib
import time

import numpy as np
import torch


def best_per_call(call, calls, repeat):
    """The smallest wall time per call over `repeat` runs of `calls` calls, in µs."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(calls):
            call()
        best = min(best, (time.perf_counter() - start) / calls)
    return best * 1e6


def measure(module, states, repeat, device):
    v = module.f64
    n, nc = module.dof, module.constraints
    generator = torch.Generator().manual_seed(1)
    q = 2 * torch.rand(states, module.nq, generator=generator, dtype=torch.float64) - 1
    qd = 4 * torch.rand(states, n, generator=generator, dtype=torch.float64) - 2
    drivers = 10 * torch.rand(states, v.drivers_size, generator=generator, dtype=torch.float64) - 5
    beta = 6 * torch.rand(states, nc, generator=generator, dtype=torch.float64) - 3
    flat = torch.cat([q, qd, drivers, beta], 1).numpy()
    weights = torch.rand(states, n, generator=generator, dtype=torch.float64)
    calls = max(1, 4096 // states) * 4 if states <= 4096 else 1
    on_device = [t.to(device) for t in (q, qd, drivers, beta, weights)]
    wait = torch.cuda.synchronize if device == "cuda" else (lambda: None)

    def torch_forward():
        q, qd, drivers, beta, _ = on_device
        module.torch.solve(q, qd, drivers, beta if nc else None)
        wait()

    def torch_backward():
        inputs = [t.clone().requires_grad_() for t in on_device[:4]]
        s = module.torch.solve(inputs[0], inputs[1], inputs[2], inputs[3] if nc else None)
        (s.qdd * on_device[4]).sum().backward()
        wait()

    # The NumPy calls up to 4 096 states (beyond, their states/s stay those of 4 096).
    numpy_too = states <= 4096
    figures = {
        "forward": (best_per_call(torch_forward, calls, repeat),
                    numpy_too and best_per_call(lambda: v.solve_flat(flat), calls, repeat)),
        "forward+backward": (best_per_call(torch_backward, calls, repeat),
                             numpy_too and best_per_call(lambda: v.derivatives(q.numpy(), qd.numpy(), drivers.numpy(),
                                                                               beta.numpy()), calls, repeat)),
    }
    for path, (layer, numpy_call) in figures.items():
        numpy_columns = (f"{numpy_call:>11.1f} {layer - numpy_call:>11.1f}" if numpy_call else f"{'-':>11} {'-':>11}")
        numpy_rate = f"{states / numpy_call * 1e6:>13,.0f}" if numpy_call else f"{'-':>13}"
        print(f"  {states:>7} {path:<17} {layer:>11.1f} {numpy_columns} {states / layer * 1e6:>13,.0f} {numpy_rate}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--module", default="panda_lean_nc6_fixed_derivatives")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs; the best counts")
    parser.add_argument("--device", default="cpu", choices=("cpu", "cuda"), help="the tensors' device")
    args = parser.parse_args()
    module = importlib.import_module(args.module)
    where = (torch.cuda.get_device_name() if args.device == "cuda"
             else f"{torch.get_num_threads()} torch thread(s)")
    print(f"{args.module}.f64 (policy {module.f64.policies[0]}), torch {torch.__version__}, {where}:")
    print(f"  {'states':>7} {'path':<17} {'torch µs':>11} {'NumPy µs':>11} {'layer µs':>11} "
          f"{'torch st/s':>13} {'NumPy st/s':>13}")
    for states in (1, 64, 4096) + ((65536, 1048576) if args.device == "cuda" else ()):
        measure(module, states, args.repeat, args.device)


if __name__ == "__main__":
    main()
