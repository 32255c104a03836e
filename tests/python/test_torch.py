"""The PyTorch layer of the scene modules (python/torch_layer.py, README "PyTorch").

Run by ctest (tests/python/CMakeLists.txt, python_torch) with PYTHONPATH the directory of the modules:
  - panda_lean_nc6_fixed_derivatives, panda_lean_nc0_derivatives (the bundled scenes that list
    derivatives), planar_floating_derivatives (a floating base with f32 derivatives) and
    gripper_coupled_derivatives (coupled <mimic> joints: q, qd of the independent joint), this
    directory's scenes: torch.autograd.gradcheck with its own tolerances, the judge of a
    backward; gradgradcheck raises (no second derivatives are generated); the forward equals the
    module's solve_flat bit for bit (one generated code path), with and without a gradient asked;
  - a floating base's rotation: its gradient against a central difference along R exp(e [w]x);
  - f32 derivatives: the backward's products equal those of the module's own Jacobians;
  - panda_nc6 (no derivatives; f64 and f32): the forward equals solve_flat; the backward says why not;
    its drivers as read from flat_in_layout;
  - what cannot be differentiated raises, naming why; bad shapes, dtypes, devices and drivers raise;
    a non-contiguous or broadcast argument gives the contiguous one's results; a NaN state is
    flagged in status and raised with raise_on_status.
"""

import importlib
import subprocess
import sys
import unittest

import numpy as np
import torch

SEED = 2026
STATES = 3  # gradcheck's numerical Jacobian takes 2 solves per input value: 3 states x 27 values x 2


def floating(module):
    """Whether q holds world_R_base (9 values) and its position for the base's 6 velocities."""
    return module.nq != module.nv


def random_state(module, generator, batch=(STATES,), dtype=torch.float64, driver_scale=10):
    """q, qd, drivers (a dict by name), beta of `batch` random states: joint angles in [-2, 2] rad,
    velocities ~N(0, 1), torques and wrenches ~N(0, driver_scale^2), setpoints ~N(0, 1); a floating
    base's rotation a random rotation (exp of a N(0, 1) rotation vector)."""
    variant = module.f64
    joints = module.nq - (9 if floating(module) else 0)
    q = 4 * torch.rand(*batch, joints, generator=generator, dtype=torch.float64) - 2
    if floating(module):
        q = torch.cat([rotation(torch.randn(*batch, 3, generator=generator, dtype=torch.float64)).flatten(-2), q], -1)
    qd = torch.randn(*batch, module.nv, generator=generator, dtype=torch.float64)
    drivers_flat = driver_scale * torch.randn(*batch, variant.drivers_size, generator=generator, dtype=torch.float64)
    beta = torch.randn(*batch, module.constraints, generator=generator, dtype=torch.float64)
    return [t.to(dtype) for t in (q, qd, drivers_flat, beta)]


def skew(w):
    """[w]x of (..., 3) vectors: (..., 3, 3)."""
    zero = torch.zeros_like(w[..., 0])
    return torch.stack([torch.stack([zero, -w[..., 2], w[..., 1]], -1),
                        torch.stack([w[..., 2], zero, -w[..., 0]], -1),
                        torch.stack([-w[..., 1], w[..., 0], zero], -1)], -2)


def rotation(w):
    return torch.matrix_exp(skew(w))


def split_drivers(module, drivers):
    """Flat drivers as the dict by name that torch.solve takes (module.torch.drivers' order)."""
    parts, offset = {}, 0
    for name, width, _ in module.torch.drivers:
        parts[name] = drivers[..., offset:offset + width]
        offset += width
    return parts


def solve_flat(module, variant, q, qd, drivers, beta, policy):
    flat = torch.cat([t.detach() for t in (q, qd, drivers, beta)], -1)
    out = getattr(module, variant).solve_flat(flat.reshape(-1, flat.shape[-1]).numpy(), policy=policy)
    out = out.reshape(flat.shape[:-1] + (out.shape[-1],))
    dof, nc = module.dof, module.constraints
    return out[..., 0:dof], out[..., 3 * dof:3 * dof + nc], out[..., dof:2 * dof], out[..., -1]


class DerivativeSceneTest:
    """A module whose scene lists derivatives; subclassed per module below (STEM)."""

    STEM = None
    DRIVER_SCALE = 10  # random_state's torques and wrenches
    DEVICE = "cpu"  # the tensors' (cuda/test_torch_cuda.py runs these tests on a GPU)

    @classmethod
    def setUpClass(cls):
        cls.m = importlib.import_module(cls.STEM)
        cls.generator = torch.Generator().manual_seed(SEED)

    def function(self, drivers_template, q_fixed=None):
        """solve's differentiable outputs as a function of (q or q's joints, qd, beta, torque drivers...)."""
        m = self.m
        names = [n for n, _, torque in m.torch.drivers if torque]
        rotation_part = None if q_fixed is None else q_fixed[..., :9]

        def f(q, qd, beta, *torques):
            drivers = dict(drivers_template)
            drivers.update(zip(names, torques))
            full_q = q if rotation_part is None else torch.cat([rotation_part if q.dim() > 1 else rotation_part[0], q], -1)
            s = m.torch.solve(full_q, qd, drivers, beta if m.constraints else None)
            return tuple(getattr(s, y) for y in m.f64.derivative_outputs)

        return f, names

    def state(self, batch):
        """random_state's tensors on DEVICE."""
        state = random_state(self.m, self.generator, batch, driver_scale=self.DRIVER_SCALE)
        return [t.to(self.DEVICE) for t in state]

    def inputs(self, batch=(STATES,)):
        q, qd, drivers, beta = self.state(batch)
        template = split_drivers(self.m, drivers)
        names = [n for n, _, torque in self.m.torch.drivers if torque]
        torques = [template[n].clone().requires_grad_() for n in names]
        q_arg = (q[..., 9:] if floating(self.m) else q).clone().requires_grad_()
        return q, q_arg, qd.requires_grad_(), beta.requires_grad_(), template, torques

    def test_gradcheck(self):
        """torch's gradcheck (its default eps 1e-6, atol 1e-5, rtol 1e-3: the judge, not loosened)
        over q (a floating base's joints), qd, beta and each torque driver; once with every
        argument (STATES,) rows and once with q shared by the rows (1-D: its gradient the sum)."""
        q, q_arg, qd, beta, template, torques = self.inputs()
        f, _ = self.function(template, q if floating(self.m) else None)
        beta_arg = beta if self.m.constraints else beta.detach()
        self.assertTrue(torch.autograd.gradcheck(f, (q_arg, qd, beta_arg, *torques)))
        shared = q_arg[0].detach().clone().requires_grad_()
        self.assertTrue(torch.autograd.gradcheck(f, (shared, qd, beta_arg, *torques)))

    def test_second_derivatives_raise(self):
        q, q_arg, qd, beta, template, torques = self.inputs()
        f, _ = self.function(template, q if floating(self.m) else None)
        with self.assertRaisesRegex(RuntimeError, rf"{self.STEM}\.torch\.solve: second derivatives are not generated"):
            torch.autograd.gradgradcheck(f, (q_arg, qd, beta, *torques))

    def test_forward_is_solve_flat(self):
        """Without a gradient the layer runs solve_flat; with one, derivatives(): both the same
        generated values bit for bit (the derivative functions' values are the solve's trace)."""
        q, qd, drivers, beta = random_state(self.m, self.generator, (5,), driver_scale=self.DRIVER_SCALE)
        want = solve_flat(self.m, "f64", q, qd, drivers, beta, "original")
        beta_arg = beta if self.m.constraints else None
        for grad in (False, True):
            got = self.m.torch.solve(q, qd.clone().requires_grad_(grad), drivers.detach() if grad else drivers, beta_arg)
            for value, expected in zip(got[:3], want[:3]):
                self.assertTrue(np.array_equal(value.detach().numpy(), expected), f"requires_grad={grad}")
            self.assertTrue(np.array_equal(got.status.numpy(), want[3].astype(np.int64)))
            self.assertEqual(got.status.dtype, torch.int64)

    def test_what_has_no_gradient_says_why(self):
        m = self.m
        q, qd, drivers, beta = self.state((2,))
        beta_arg = beta if m.constraints else None
        not_listed = [y for y in ("qdd", "nu", "tau_cmd") if y not in m.f64.derivative_outputs
                      and (y != "nu" or m.constraints)]
        for y in not_listed:
            s = m.torch.solve(q, qd.clone().requires_grad_(), drivers, beta_arg)
            with self.assertRaisesRegex(RuntimeError, rf"the Jacobians of {y} are not generated .*: add {y} to it"):
                getattr(s, y).sum().backward()
        for policy in (p for p in m.f64.policies if p not in m.f64.derivative_policies):
            s = m.torch.solve(q, qd.clone().requires_grad_(), drivers, beta_arg, policy=policy)
            with self.assertRaisesRegex(RuntimeError, rf"no gradient: policy '{policy}' is not differentiable"):
                s.qdd.sum().backward()
        others = [n for n, _, torque in m.torch.drivers if not torque]
        if others:
            s = m.torch.solve(q, qd, drivers.clone().requires_grad_(), beta_arg)
            with self.assertRaisesRegex(RuntimeError, rf"no gradient for the drivers {', '.join(others)}"):
                s.qdd.sum().backward()


class PandaNc6Fixed(DerivativeSceneTest, unittest.TestCase):
    STEM = "panda_lean_nc6_fixed_derivatives"


class PandaNc0(DerivativeSceneTest, unittest.TestCase):
    STEM = "panda_lean_nc0_derivatives"


class CoupledJoints(DerivativeSceneTest, unittest.TestCase):
    """q and qd hold finger_joint alone; its columns carry the five coupled joints' shares (D8).
    The hand's links weigh 10 to 30 g: torques of 10 N m drive q̈ to ~1e4 rad/s², whose rounding
    (ε κ |q̈| ~ 1e-12 at the E of five couplings) over gradcheck's step of 2e-6 reaches its atol of
    1e-5 where the true derivative is about 0 (the fingers' linkages keep the hand's inertia about
    finger_joint nearly constant, so q̈ hardly depends on q̇); the hand's own torques are tenths of
    a N m."""
    STEM = "gripper_coupled_derivatives"
    DRIVER_SCALE = 0.1


class FloatingBase(DerivativeSceneTest, unittest.TestCase):
    STEM = "planar_floating_derivatives"

    def test_rotation_gradient_along_the_rotations(self):
        """d/de y(R exp(e [w]x)) at e = 0 is <grad_R, R [w]x>: the central difference with e = 1e-5
        has truncation error e^2/6 |y'''| and rounding about eps |y| / e, each below 1e-9 relative for
        |y| up to 1e4 here; judged with gradcheck's own tolerances (atol 1e-5, rtol 1e-3)."""
        m = self.m
        q, qd, drivers, beta = random_state(m, self.generator, (4,))
        q = q.clone().requires_grad_()
        weights = torch.randn(4, m.dof, generator=self.generator, dtype=torch.float64)
        (m.torch.solve(q, qd, drivers, beta).qdd * weights).sum().backward()
        w = torch.randn(4, 3, generator=self.generator, dtype=torch.float64)
        R = q.detach()[:, :9].reshape(4, 3, 3)
        e = 1e-5

        def objective(sign):
            moved = torch.cat([(R @ rotation(sign * e * w)).reshape(4, 9), q.detach()[:, 9:]], 1)
            return (m.torch.solve(moved, qd, drivers, beta).qdd * weights).sum(-1)

        numerical = (objective(1) - objective(-1)) / (2 * e)
        analytical = (q.grad[:, :9].reshape(4, 3, 3) * (R @ skew(w))).sum((-1, -2))
        self.assertTrue(torch.allclose(analytical, numerical, rtol=1e-3, atol=1e-5), f"{analytical} {numerical}")

    def test_float_derivatives(self):
        """float32 tensors go to the f32 variant and its derivatives(): the backward's products
        equal the module's own f32 Jacobians times the same weights, up to the order of a dot
        product's float additions (dof terms: dof eps_f times the sum of |terms|)."""
        m = self.m
        q, qd, drivers, beta = random_state(m, self.generator, (4,), torch.float32)
        qd = qd.clone().requires_grad_()
        s = m.torch.solve(q, qd, drivers, beta)
        self.assertEqual(s.qdd.dtype, torch.float32)
        weights = torch.randn(4, m.dof, generator=self.generator, dtype=torch.float32)
        (s.qdd * weights).sum().backward()
        jacobian = torch.from_numpy(m.f32.derivatives(q.numpy(), qd.detach().numpy(), drivers.numpy(),
                                                      beta.numpy())["d_qdd_dqd"])
        terms = weights.unsqueeze(-1) * jacobian
        bound = m.dof * np.finfo(np.float32).eps * terms.abs().sum(1)
        self.assertTrue(torch.all((qd.grad - terms.sum(1)).abs() <= bound), f"{qd.grad} {terms.sum(1)}")


class WithoutDerivatives(unittest.TestCase):
    """panda_nc6: no derivatives, f64 and f32, run-time directions among its drivers."""

    @classmethod
    def setUpClass(cls):
        cls.m = importlib.import_module("panda_nc6")
        cls.generator = torch.Generator().manual_seed(SEED)

    def test_forward_is_solve_flat_in_both_scalars(self):
        m = self.m
        for variant, dtype in (("f64", torch.float64), ("f32", torch.float32)):
            q, qd, drivers, beta = random_state(m, self.generator, (2, 3), dtype)
            want = solve_flat(m, variant, q, qd, drivers, beta, "saturate")
            got = m.torch.solve(q, qd, drivers, beta, policy="saturate")
            self.assertEqual(got.qdd.shape, (2, 3, m.dof))
            self.assertEqual(got.status.shape, (2, 3))
            for value, expected in zip(got[:3], want[:3]):
                self.assertEqual(value.dtype, dtype)
                self.assertTrue(np.array_equal(value.numpy(), expected), variant)
            by_name = m.torch.solve(q, qd, split_drivers(m, drivers), beta, policy="saturate")
            self.assertTrue(torch.equal(by_name.qdd, got.qdd))

    def test_drivers_read_from_the_flat_layout(self):
        """module.torch.drivers, read from flat_in_layout: panda_nc6's torque, two wrenches and six
        run-time directions (robots/panda/panda_nc6.yaml)."""
        self.assertEqual(self.m.torch.drivers, (("tau_ff", 7, True), ("contact", 6, False), ("push", 6, False),
                                                ("alpha", 36, False)))

    def test_broadcast_and_non_contiguous_arguments(self):
        """A 1-D argument is shared by every row; a non-contiguous one is copied: the results of
        the same states given as contiguous rows."""
        m = self.m
        q, qd, drivers, beta = random_state(m, self.generator, (4,))
        shared = m.torch.solve(q[1], qd, drivers, beta)
        rows = m.torch.solve(q[1].expand(4, -1).contiguous(), qd, drivers, beta)
        self.assertTrue(torch.equal(shared.qdd, rows.qdd))
        wide = torch.stack([qd, torch.zeros_like(qd)], -1)  # qd as every other value of a buffer
        strided = m.torch.solve(q, wide[..., 0], drivers, beta)
        self.assertFalse(wide[..., 0].is_contiguous())
        self.assertTrue(torch.equal(strided.qdd, m.torch.solve(q, qd, drivers, beta).qdd))

    def test_backward_says_the_scene_has_no_derivatives(self):
        m = self.m
        q, qd, drivers, beta = random_state(m, self.generator, (2,))
        s = m.torch.solve(q.clone().requires_grad_(), qd, drivers, beta)
        with self.assertRaisesRegex(RuntimeError, r"panda_nc6\.torch\.solve: no gradient: the scene has no derivatives: "
                                                  r"add the scene key `derivatives`"):
            s.qdd.sum().backward()
        s.status.sum()  # status is returned without a gradient: no backward through it
        self.assertFalse(s.status.requires_grad)

    def test_bad_arguments(self):
        m = self.m
        q, qd, drivers, beta = random_state(m, self.generator, (2,))
        cases = [
            (ValueError, r"qd has shape \(2, 6\); it needs \(\.\.\., 7\)", (q, qd[:, :6], drivers, beta), {}),
            (RuntimeError, r"shape", (q[:1].expand(3, -1), qd, drivers, beta), {}),  # batch shapes 3 and 2
            (TypeError, r"q is torch\.int64; this scene's variants take torch\.float64 or torch\.float32",
             (q.long(), qd, drivers, beta), {}),
            (TypeError, r"beta is torch\.float32, q is torch\.float64", (q, qd, drivers, beta.float()), {}),
            (TypeError, r"qd must be a torch\.Tensor, not ndarray", (q, qd.numpy(), drivers, beta), {}),
            (ValueError, r"q is on meta; this module runs on the CPU \(built without CUDA kernels\): move it with "
                         r"\.cpu\(\)", (q.to("meta"), qd, drivers, beta), {}),
            (ValueError, r"beta is None, but this scene has 6 values of it", (q, qd, drivers, None), {}),
            (ValueError, r"'fastest' is not a policy of this scene", (q, qd, drivers, beta), {"policy": "fastest"}),
            (ValueError, r"not drivers of this scene: wind; missing: push; the scene's: tau_ff, contact, push, alpha",
             (q, qd, {**{k: v for k, v in split_drivers(m, drivers).items() if k != "push"}, "wind": q}, beta), {}),
        ]
        for error, message, arguments, keywords in cases:
            with self.assertRaisesRegex(error, message):
                m.torch.solve(*arguments, **keywords)

    def test_a_nan_state_is_flagged_and_raised_on_request(self):
        m = self.m
        q, qd, drivers, beta = random_state(m, self.generator, (3,))
        q[1, 2] = float("nan")
        s = m.torch.solve(q, qd, drivers, beta)
        self.assertEqual([bool(v & m.Status.not_finite) for v in s.status.tolist()], [False, True, False])
        with self.assertRaises(m.SolverStatusError) as raised:
            m.torch.solve(q, qd, drivers, beta, raise_on_status=m.Status.not_finite)
        self.assertEqual(raised.exception.index, 1)

    def test_importing_the_module_does_not_import_torch(self):
        """torch is imported by <module>.torch, not by the module; without torch it says what to install."""
        code = ("import sys; sys.modules['torch'] = None; import panda_nc6\n"
                "try:\n    panda_nc6.torch\nexcept ImportError as e:\n    print(e)")
        printed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
        self.assertRegex(printed, r"^panda_nc6\.torch needs PyTorch in .* \(Debian: python3-torch\)")
        with self.assertRaisesRegex(AttributeError, "module 'panda_nc6' has no attribute 'tensorflow'"):
            self.m.tensorflow


if __name__ == "__main__":
    unittest.main(verbosity=2)
