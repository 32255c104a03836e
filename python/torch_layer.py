"""The PyTorch layer of a sweepgen scene module (README, "PyTorch"): `<module>.torch`.

python/module.cpp holds this file's text and runs it the first time `<module>.torch` is read, so
that importing a module never imports torch. `bind(module)` returns the namespace that
`<module>.torch` is:

    solve(q, qd, drivers=None, beta=None, *, policy=None, raise_on_status=0) -> Solution

a `torch.autograd.Function` over the module's generated code:
  - the arguments as the module's solve(): q (..., nq), qd (..., nv), beta (..., constraints) and
    drivers (..., drivers_size) the flat drivers, or a dict of the drivers by name (the names of
    the module's flat_in_layout, e.g. {"tau_ff": ..., "push": ...}), so that each has a gradient
    of its own; leading batch shapes broadcast; float64 tensors go to the module's f64 variant,
    float32 to f32; every argument on one device: the CPU, or a CUDA device where the module has
    CUDA kernels (`<module>.cuda`: built with its solver's CUDA library);
  - forward on the CPU: the generated batch entry points (`solve_batch` on the rows; with a
    gradient asked for, `derivatives`, which returns the values and their Jacobians in one pass); a
    contiguous tensor of the batch's shape reaches the module without a copy (a NumPy view, from
    which the module gathers each state's values into the batch's lanes), others are copied once;
  - forward on a GPU: the generated kernels (`<solve>_cuda`, `derivatives_<policy>_cuda`: a thread
    per state) on the tensors' device, queued on torch's current stream: the arguments copied once
    into the kernels' layout (value k of state s at [k * K + s]), the results returned as views of
    the kernels' output, nothing copied to or from the host (but a status to raise on, where
    raise_on_status asks);
  - backward: vector-Jacobian products with the generated Jacobians (docs/derivation.md, D2, D3):
    the columns of q, qd, the torque drivers (each receives the tau_ff columns: the torque drivers
    are summed, D2) and beta. A floating base's q holds world_R_base (9, row-major): its gradient
    is R [g/2]x with g the gradient of the rotation-vector columns (D2: R -> R exp([dtheta]x)),
    the gradient in R's tangent space, which a step along the rotations sees and a step off them
    does not. On a GPU the products are torch's batched matrix products on the device.

What cannot be differentiated raises at backward, naming why: a scene without the key
`derivatives`, a policy that clamps (saturate), an output whose Jacobian the scene's list leaves
out, a driver that is not a torque (its columns are not generated), a variant without derivatives,
a second derivative (none is generated).
"""

import collections
import re

import numpy as np
import torch

Solution = collections.namedtuple("Solution", ["qdd", "nu", "tau_cmd", "status"])
Solution.__doc__ = ("qdd, tau_cmd (..., dof), nu (..., constraints): tensors of the inputs' dtype; status (...): "
                    "int64, the module's Status flags")

_OUTPUTS = ("qdd", "nu", "tau_cmd")
_BLOCKS = ("dq", "dqd", "dtau_ff", "dbeta")  # (D2)'s column blocks, the module's d_<y>_<block>


def _driver_layout(module):
    """The drivers in the module's flat_in_layout ('q (nq), qd (dof), tau_ff (dof), push (6),
    alpha (constraints x 6), beta (constraints)'): [(name, width, is_torque)]; a torque driver is
    one value per joint."""
    sizes = {"dof": module.dof, "nq": module.nq, "nv": module.nv, "constraints": module.constraints}
    parts = []
    for part, width in re.findall(r"(\w+) \(([^)]*)\)", module.flat_in_layout):
        size = 1
        for factor in width.split(" x "):
            factor = factor.strip()
            if not factor.isdigit() and factor not in sizes:
                raise RuntimeError(f"{module.__name__}.torch: cannot read the width '{width}' of '{part}' in "
                                   f"flat_in_layout '{module.flat_in_layout}'")
            size *= int(factor) if factor.isdigit() else sizes[factor]
        parts.append((part, size, width == "dof"))
    names = [p[0] for p in parts]
    if names[:2] != ["q", "qd"] or (module.constraints > 0) != (names[-1] == "beta"):
        raise RuntimeError(f"{module.__name__}.torch: unexpected flat_in_layout '{module.flat_in_layout}'")
    return parts[2:len(parts) - (module.constraints > 0)]


def bind(module):
    name = module.__name__
    dof, nq, nv, nc = module.dof, module.nq, module.nv, module.constraints
    floating = nq != nv  # world_R_base's nine values for the six [dtheta; dp] columns (D2)
    variants = {getattr(torch, dtype): getattr(module, scalar)
                for scalar, dtype in (("f64", "float64"), ("f32", "float32")) if scalar in module.scalars}
    layout = _driver_layout(module)
    drivers_size = next(iter(variants.values())).drivers_size
    if sum(width for _, width, _ in layout) != drivers_size:
        raise RuntimeError(f"{name}.torch: flat_in_layout '{module.flat_in_layout}' does not add up to drivers_size "
                           f"{drivers_size}")

    def check(argument, value, width, dtype, device):
        """value: a tensor (..., width) of dtype on device (q's), or None where width is 0."""
        if value is None:
            if width == 0:
                return None
            raise ValueError(f"{name}.torch.solve: {argument} is None, but this scene has {width} values of it")
        if not isinstance(value, torch.Tensor):
            raise TypeError(f"{name}.torch.solve: {argument} must be a torch.Tensor, not {type(value).__name__}")
        if value.device.type == "cuda" and not module.cuda:
            raise ValueError(f"{name}.torch.solve: {argument} is on {value.device}; this module has no CUDA kernels "
                             f"(built without its solver's CUDA library: README, \"PyTorch\"): move it with .cpu()")
        if value.device.type not in ("cpu", "cuda"):
            raise ValueError(f"{name}.torch.solve: {argument} is on {value.device}; this module runs on the CPU "
                             + ("or a CUDA device" if module.cuda else "(built without CUDA kernels)")
                             + ": move it with .cpu()")
        if value.device != device:
            raise ValueError(f"{name}.torch.solve: {argument} is on {value.device}, q on {device}: give every "
                             f"argument one device")
        if value.dtype != dtype:
            raise TypeError(f"{name}.torch.solve: {argument} is {value.dtype}, q is {dtype}: give every argument "
                            f"one dtype")
        if value.dim() == 0 or value.shape[-1] != width:
            raise ValueError(f"{name}.torch.solve: {argument} has shape {tuple(value.shape)}; it needs (..., {width})")
        return value

    def driver_parts(drivers, dtype, device):
        """The drivers as given, [(tensor, [(name, width, is_torque)] it holds)]."""
        if isinstance(drivers, dict):
            unknown = sorted(set(drivers) - {part for part, _, _ in layout})
            missing = [part for part, _, _ in layout if part not in drivers]
            if unknown or missing:
                raise ValueError(f"{name}.torch.solve: drivers {sorted(drivers)}: "
                                 + (f"not drivers of this scene: {', '.join(unknown)}; " if unknown else "")
                                 + (f"missing: {', '.join(missing)}; " if missing else "")
                                 + f"the scene's: {', '.join(part for part, _, _ in layout)}")
            return [(check(f"drivers['{part}']", drivers[part], width, dtype, device), [(part, width, torque)])
                    for part, width, torque in layout]
        value = check("drivers", drivers, drivers_size, dtype, device)
        return [(value, layout)] if value is not None else []

    def rows(value, batch, width):
        """(K, width) NumPy rows of value broadcast to batch: a view where value is contiguous and
        of the batch's shape, else one copy."""
        if value.shape[:-1] == batch and value.is_contiguous():
            return value.detach().numpy().reshape(-1, width)
        return value.detach().expand(batch + (width,)).reshape(-1, width).contiguous().numpy()

    def solve_values(out):
        """qdd, nu, tau_cmd and status (int64) of solves' flat outputs (K, flat_out_size), views of out;
        flat_out_layout: qdd (dof), tau_cmd (dof), tau_ctrl (dof), nu (constraints), tip (6), status."""
        return [out[:, 0:dof], out[:, 3 * dof:3 * dof + nc], out[:, dof:2 * dof]], out[:, -1].to(torch.int64)

    def on_cpu(ctx, variant, policy, mask, q, qd, beta, drivers, batch, differentiate):
        """The forward on the CPU (the module's batch entry points): qdd, nu, tau_cmd (K, rows) and
        status (K,) tensors; with differentiate, ctx.jacobians too."""
        q_rows, qd_rows = rows(q, batch, nq), rows(qd, batch, nv)
        b_rows = rows(beta, batch, nc) if beta is not None else None
        d_rows = [rows(d, batch, d.shape[-1]) for d in drivers]
        d_rows = None if not d_rows else d_rows[0] if len(d_rows) == 1 else np.concatenate(d_rows, 1)
        if differentiate:
            result = variant.derivatives(q_rows, qd_rows, d_rows, b_rows, policy=policy, raise_on_status=mask)
            ctx.jacobians = {y: [torch.from_numpy(result[f"d_{y}_{b}"]) for b in _BLOCKS]
                             for y in variant.derivative_outputs}
            if floating:
                ctx.base_rotation = torch.from_numpy(q_rows[:, :9]).reshape(-1, 3, 3)
            return [torch.from_numpy(result[y]) for y in _OUTPUTS], torch.from_numpy(result["status"].astype(np.int64))
        return solve_values(torch.from_numpy(variant.solve_batch(q_rows, qd_rows, d_rows, b_rows, policy=policy,
                                                                 raise_on_status=mask)))

    def on_gpu(ctx, variant, policy, mask, q, qd, beta, drivers, batch, differentiate):
        """The forward on q's CUDA device (the module's kernels on torch's current stream): what
        on_cpu returns, views of the kernels' output."""
        given = [v for v in (q, qd, *drivers, beta) if v is not None]
        states = batch.numel()
        columns = torch.empty((variant.flat_in_size, states), dtype=q.dtype, device=q.device)
        first = 0
        for value in given:  # the kernels' layout: value k of state s at [k * states + s]
            width = value.shape[-1]
            columns[first:first + width].copy_(value.expand(batch + (width,)).reshape(states, width).t())
            first += width
        out_size = variant.derivative_flat_out_size if differentiate else variant.flat_out_size
        out = torch.empty((out_size, states), dtype=q.dtype, device=q.device)
        launch = variant._derivatives_cuda if differentiate else variant._solve_cuda
        with torch.cuda.device(q.device):
            launch(states, columns.data_ptr(), out.data_ptr(), torch.cuda.current_stream().cuda_stream, policy=policy)
        out = out.t()  # (states, out_size)
        status = out[:, -1].to(torch.int64)
        if mask:  # the statuses read back only where raise_on_status asks
            variant._raise_on_status(status.cpu().numpy(), "derivatives_cuda" if differentiate else "solve_cuda",
                                     policy, mask)
        if not differentiate:
            return solve_values(out)
        # derivatives' flat output: qdd (dof), nu (constraints), tau_cmd (dof), the Jacobians returned
        # (rows x derivative_columns each, derivative_outputs' order), status
        values = [out[:, 0:dof], out[:, dof:dof + nc], out[:, dof + nc:2 * dof + nc]]
        columns_of = variant.derivative_columns
        widths = (nv, nv, dof, nc)  # (D2)'s column blocks: q, qd, tau_ff, beta
        starts = np.cumsum((0,) + widths)
        first, ctx.jacobians = 2 * dof + nc, {}
        for y in variant.derivative_outputs:
            height = dof if y != "nu" else nc
            jacobian = out[:, first:first + height * columns_of].reshape(states, height, columns_of)
            first += height * columns_of
            ctx.jacobians[y] = [jacobian[:, :, starts[k]:starts[k + 1]] for k in range(4)]
        if floating:
            ctx.base_rotation = q.detach().expand(batch + (nq,)).reshape(states, nq)[:, :9].reshape(-1, 3, 3)
        return values, status

    class Solve(torch.autograd.Function):
        @staticmethod
        def forward(ctx, policy, mask, holds, q, qd, beta, *drivers):
            dtype = q.dtype
            variant = variants[dtype]
            given = [q, qd, beta, *drivers]
            shapes = [v.shape[:-1] for v in given if v is not None]
            batch = (shapes[0] if all(shape == shapes[0] for shape in shapes)
                     else torch.Size(torch.broadcast_shapes(*shapes)))
            ctx.set_materialize_grads(False)
            ctx.batch, ctx.dtype, ctx.holds = batch, dtype, holds
            ctx.shapes = [None if v is None else v.shape for v in given]
            ctx.jacobians = None
            ctx.why_not = why_not_differentiable(variant, policy) if any(ctx.needs_input_grad[3:]) else None
            differentiate = any(ctx.needs_input_grad[3:]) and ctx.why_not is None
            forward = on_gpu if q.device.type == "cuda" else on_cpu
            values, status = forward(ctx, variant, policy, mask, q, qd, beta, drivers, batch, differentiate)
            status = status.reshape(batch)
            ctx.mark_non_differentiable(status)
            ctx.save_for_backward(*given)
            return (*(v.reshape(batch + v.shape[1:]) for v in values), status)

        @staticmethod
        def backward(ctx, *grads):
            wanted = [k for k in range(len(ctx.shapes)) if ctx.needs_input_grad[3 + k]]
            if all(g is None for g in grads[:3]):
                return (None,) * (3 + len(ctx.shapes))
            products = dict(zip(wanted, SecondOrder.apply(ctx, wanted, *grads[:3], *ctx.saved_tensors)))
            return (None, None, None, *(products.get(k) for k in range(len(ctx.shapes))))

    class SecondOrder(torch.autograd.Function):
        """Solve's backward as a function of its own whose inputs are Solve's too: a second
        derivative through it raises (none is generated), where torch would read a backward that
        no graph links to q as a zero second derivative."""

        @staticmethod
        def forward(ctx, solve_ctx, wanted, g_qdd, g_nu, g_tau_cmd, *inputs):
            products = vector_jacobian_products(solve_ctx, {"qdd": g_qdd, "nu": g_nu, "tau_cmd": g_tau_cmd})
            return tuple(products[k] for k in wanted)

        @staticmethod
        def backward(ctx, *grads):
            raise RuntimeError(f"{name}.torch.solve: second derivatives are not generated (docs/derivation.md, D3: "
                               f"first derivatives only)")

    def vector_jacobian_products(ctx, g):
        """g^T dy/dx (D3), summed over the outputs y with a gradient, for the inputs x of Solve
        (q, qd, beta, each drivers tensor), each shaped as its input; None where not asked for."""
        asked = [y for y in _OUTPUTS if g[y] is not None]
        if ctx.jacobians is None:
            raise RuntimeError(f"{name}.torch.solve: no gradient: {ctx.why_not}")
        missing = [y for y in asked if y not in ctx.jacobians]
        if missing:
            raise RuntimeError(f"{name}.torch.solve: the Jacobians of {', '.join(missing)} are not generated (scene "
                               f"key derivatives lists {', '.join(ctx.jacobians)}): add {', '.join(missing)} to it")
        blocks = [None] * 4
        for y in asked:
            gy = g[y].reshape(-1, 1, g[y].shape[-1]).to(ctx.dtype)
            for k, jacobian in enumerate(ctx.jacobians[y]):
                product = torch.bmm(gy, jacobian).squeeze(1)  # one row per state
                blocks[k] = product if blocks[k] is None else blocks[k] + product
        grad_q, grad_qd, grad_tau_ff, grad_beta = blocks
        if floating:  # [dtheta; dp] lead the q columns (D2); nothing reads the base's position
            half = grad_q[:, 0:3] / 2
            skew = torch.zeros(half.shape[0], 3, 3, dtype=half.dtype, device=half.device)
            skew[:, 0, 1], skew[:, 0, 2], skew[:, 1, 2] = -half[:, 2], half[:, 1], -half[:, 0]
            skew = skew - skew.transpose(1, 2)
            grad_q = torch.cat([torch.bmm(ctx.base_rotation, skew).reshape(-1, 9), grad_q[:, 6:]], 1)
        grads = [grad_q, grad_qd, grad_beta]
        for k, holds in enumerate(ctx.holds):
            if not ctx.needs_input_grad[6 + k]:
                grads.append(None)
                continue
            others = [part for part, _, torque in holds if not torque]
            if others:
                raise RuntimeError(f"{name}.torch.solve: no gradient for the drivers {', '.join(others)}: their "
                                   f"Jacobian columns are not generated, only the torque drivers' (docs/derivation.md, "
                                   f"D2); give the drivers as a dict by name, those without gradient not requiring it")
            grads.append(torch.cat([grad_tau_ff] * len(holds), 1))

        def shaped(grad, k):
            if grad is None or not ctx.needs_input_grad[3 + k]:
                return None
            return grad.reshape(ctx.batch + (grad.shape[-1],)).sum_to_size(ctx.shapes[k])

        return [shaped(grad, k) for k, grad in enumerate(grads)]

    def why_not_differentiable(variant, policy):
        if not hasattr(variant, "derivatives"):
            if any(hasattr(v, "derivatives") for v in variants.values()):
                return f"the {variant.dtype} variant has no derivatives"
            return f"the scene has no derivatives: add the scene key `derivatives` (docs/scene.md) and rebuild {name}"
        if policy not in variant.derivative_policies:
            return (f"policy '{policy}' is not differentiable (it clamps torques at their limits); differentiable: "
                    f"{', '.join(variant.derivative_policies)}")
        return None

    def solve(q, qd, drivers=None, beta=None, *, policy=None, raise_on_status=0):
        """outward + decompose + solve_<policy> with autograd; see help(<module>.torch)."""
        if not isinstance(q, torch.Tensor):
            raise TypeError(f"{name}.torch.solve: q must be a torch.Tensor, not {type(q).__name__}")
        if q.dtype not in variants:
            raise TypeError(f"{name}.torch.solve: q is {q.dtype}; this scene's variants take "
                            f"{' or '.join(str(d) for d in variants)} (scene key scalars)")
        variant = variants[q.dtype]
        q = check("q", q, nq, q.dtype, q.device)
        qd = check("qd", qd, nv, q.dtype, q.device)
        beta = check("beta", beta, nc, q.dtype, q.device)
        parts = driver_parts(drivers, q.dtype, q.device)
        policy = variant.policies[0] if policy is None else policy
        if policy not in variant.policies:
            raise ValueError(f"{name}.torch.solve: '{policy}' is not a policy of this scene "
                             f"({', '.join(variant.policies)})")
        holds = [part_layout for _, part_layout in parts]
        return Solution(*Solve.apply(policy, int(raise_on_status), holds, q, qd, beta, *(t for t, _ in parts)))

    namespace = type(module)(f"{name}.torch", __doc__)
    namespace.solve = solve
    namespace.Solution = Solution
    namespace.drivers = tuple(layout)  # (name, width, is_torque): the keys of solve()'s drivers dict
    return namespace
