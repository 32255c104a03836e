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
    float32 to f32; CPU tensors (the module has no CUDA kernels);
  - forward: the generated batch entry points (`solve_batch` on the rows; with a gradient asked
    for, `derivatives`, which returns the values and their Jacobians in one pass); a contiguous
    tensor of the batch's shape reaches the module without a copy (a NumPy view, from which the
    module gathers each state's values into the batch's lanes), others are copied once;
  - backward: vector-Jacobian products with the generated Jacobians (docs/derivation.md, D2, D3):
    the columns of q, qd, the torque drivers (each receives the tau_ff columns: the torque drivers
    are summed, D2) and beta. A floating base's q holds world_R_base (9, row-major): its gradient
    is R [g/2]x with g the gradient of the rotation-vector columns (D2: R -> R exp([dtheta]x)),
    the gradient in R's tangent space, which a step along the rotations sees and a step off them
    does not.

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

    def check(argument, value, width, dtype):
        """value: a tensor (..., width) on the CPU of dtype, or None where width is 0."""
        if value is None:
            if width == 0:
                return None
            raise ValueError(f"{name}.torch.solve: {argument} is None, but this scene has {width} values of it")
        if not isinstance(value, torch.Tensor):
            raise TypeError(f"{name}.torch.solve: {argument} must be a torch.Tensor, not {type(value).__name__}")
        if value.device.type != "cpu":
            raise ValueError(f"{name}.torch.solve: {argument} is on {value.device}; this module runs on the CPU "
                             f"(built without CUDA kernels): move it with .cpu()")
        if value.dtype != dtype:
            raise TypeError(f"{name}.torch.solve: {argument} is {value.dtype}, q is {dtype}: give every argument "
                            f"one dtype")
        if value.dim() == 0 or value.shape[-1] != width:
            raise ValueError(f"{name}.torch.solve: {argument} has shape {tuple(value.shape)}; it needs (..., {width})")
        return value

    def driver_parts(drivers, dtype):
        """The drivers as given, [(tensor, [(name, width, is_torque)] it holds)]."""
        if isinstance(drivers, dict):
            unknown = sorted(set(drivers) - {part for part, _, _ in layout})
            missing = [part for part, _, _ in layout if part not in drivers]
            if unknown or missing:
                raise ValueError(f"{name}.torch.solve: drivers {sorted(drivers)}: "
                                 + (f"not drivers of this scene: {', '.join(unknown)}; " if unknown else "")
                                 + (f"missing: {', '.join(missing)}; " if missing else "")
                                 + f"the scene's: {', '.join(part for part, _, _ in layout)}")
            return [(check(f"drivers['{part}']", drivers[part], width, dtype), [(part, width, torque)])
                    for part, width, torque in layout]
        value = check("drivers", drivers, drivers_size, dtype)
        return [(value, layout)] if value is not None else []

    def rows(value, batch, width):
        """(K, width) NumPy rows of value broadcast to batch: a view where value is contiguous and
        of the batch's shape, else one copy."""
        if value.shape[:-1] == batch and value.is_contiguous():
            return value.detach().numpy().reshape(-1, width)
        return value.detach().expand(batch + (width,)).reshape(-1, width).contiguous().numpy()

    def tensor(values, batch):
        """A tensor over NumPy values (K, width) (no copy), shaped batch + (width,)."""
        return torch.from_numpy(values.reshape(batch + values.shape[1:]))

    class Solve(torch.autograd.Function):
        @staticmethod
        def forward(ctx, policy, mask, holds, q, qd, beta, *drivers):
            dtype = q.dtype
            variant = variants[dtype]
            given = [q, qd, beta, *drivers]
            shapes = [v.shape[:-1] for v in given if v is not None]
            batch = (shapes[0] if all(shape == shapes[0] for shape in shapes)
                     else torch.Size(torch.broadcast_shapes(*shapes)))
            q_rows, qd_rows = rows(q, batch, nq), rows(qd, batch, nv)
            b_rows = rows(beta, batch, nc) if beta is not None else None
            d_rows = [rows(d, batch, d.shape[-1]) for d in drivers]
            d_rows = None if not d_rows else d_rows[0] if len(d_rows) == 1 else np.concatenate(d_rows, 1)
            ctx.set_materialize_grads(False)
            ctx.batch, ctx.dtype, ctx.holds = batch, dtype, holds
            ctx.shapes = [None if v is None else v.shape for v in given]
            ctx.jacobians = None
            ctx.why_not = why_not_differentiable(variant, policy) if any(ctx.needs_input_grad[3:]) else None
            if any(ctx.needs_input_grad[3:]) and ctx.why_not is None:
                result = variant.derivatives(q_rows, qd_rows, d_rows, b_rows, policy=policy, raise_on_status=mask)
                values = [result[y] for y in _OUTPUTS]
                status = result["status"].astype(np.int64)
                ctx.jacobians = {y: [torch.from_numpy(result[f"d_{y}_{b}"]) for b in _BLOCKS]
                                 for y in variant.derivative_outputs}
                if floating:
                    ctx.base_rotation = torch.from_numpy(q_rows[:, :9]).reshape(-1, 3, 3)
            else:
                out = variant.solve_batch(q_rows, qd_rows, d_rows, b_rows, policy=policy, raise_on_status=mask)
                # flat_out_layout: qdd (dof), tau_cmd (dof), tau_ctrl (dof), nu (constraints), tip (6), status
                values = [out[:, 0:dof], out[:, 3 * dof:3 * dof + nc], out[:, dof:2 * dof]]
                status = out[:, -1].astype(np.int64)
            status = torch.from_numpy(status.reshape(batch))
            ctx.mark_non_differentiable(status)
            ctx.save_for_backward(*given)
            return (*(tensor(v, batch) for v in values), status)

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
            skew = torch.zeros(half.shape[0], 3, 3, dtype=half.dtype)
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
        q = check("q", q, nq, q.dtype)
        qd = check("qd", qd, nv, q.dtype)
        beta = check("beta", beta, nc, q.dtype)
        parts = driver_parts(drivers, q.dtype)
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
