"""The PyTorch layer on a GPU (python/torch_layer.py, README "PyTorch"): CUDA tensors through the
modules' CUDA kernels. Run by tests/python/cuda/run.sh on a machine with an NVIDIA GPU, with
PYTHONPATH the directory of the modules it builds (each with its solver's CUDA library but
panda_nc6, built without, as in the main build):
  - test_torch.py's derivative tests (gradcheck with torch's own tolerances, the judge of a
    backward; second derivatives raise; what has no gradient says why) with every tensor on the
    GPU, on the same scenes: a fixed base with and without constraints, a floating base, coupled
    <mimic> joints;
  - the GPU's forward, with and without a gradient asked for, and its backward against the CPU's
    (the same generated code, compiled by nvcc, which contracts multiplies and adds into FMAs: not
    bit for bit), judged by torch.testing.assert_close's defaults for the dtype; status words equal;
  - results stay on the tensors' device; float32; broadcast and non-contiguous arguments; a NaN
    state flagged and raised; arguments on two devices, and CUDA tensors for a module without
    kernels, raise.
Without a CUDA device it fails at once: it exists to test the GPU path.
"""

import os
import sys
import unittest

import torch

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import test_torch  # noqa: E402  (tests/python/test_torch.py: its scenes and helpers)
from test_torch import SEED, floating, random_state, split_drivers  # noqa: E402

DEVICE = "cuda"


class OnTheGpu:
    """test_torch.DerivativeSceneTest's tests with the tensors on the GPU, and the GPU against the CPU."""

    DEVICE = DEVICE

    # Replaced on the GPU by test_gpu_against_cpu (FMA contraction: not bit for bit); not a test here.
    test_forward_is_solve_flat = None

    def solve(self, state, grad, dtype=torch.float64):
        """torch.solve's outputs and the gradients of a weighted sum of the differentiable outputs with
        respect to q's joints, qd, beta and the torque drivers (grad), on the state's device."""
        m = self.m
        q, qd, drivers, beta = [t.to(dtype) for t in state]
        template = split_drivers(m, drivers)
        names = [n for n, _, torque in m.torch.drivers if torque]
        leaves = [qd, beta] + [template[n] for n in names] if grad else []
        leaves = [t.clone().requires_grad_() for t in leaves]
        if grad:
            qd, beta = leaves[0], leaves[1]
            template.update(zip(names, leaves[2:]))
        s = m.torch.solve(q, qd, template, beta if m.constraints else None)
        grads = []
        if grad:
            generator = torch.Generator().manual_seed(SEED)
            total = sum((getattr(s, y) * torch.randn(getattr(s, y).shape, generator=generator,
                                                     dtype=dtype).to(q.device)).sum()
                        for y in m.f64.derivative_outputs)
            total.backward()
            grads = [t.grad for t in leaves if t.grad is not None]
        return s, grads

    def test_gpu_against_cpu(self):
        """Forward without a gradient (the solve kernel), with one (the derivatives kernel) and the
        backward's products: the GPU's against the CPU's on the same states, shape (2, 3)."""
        state = random_state(self.m, self.generator, (2, 3), driver_scale=self.DRIVER_SCALE)
        for grad in (False, True):
            cpu, cpu_grads = self.solve(state, grad)
            gpu, gpu_grads = self.solve([t.to(DEVICE) for t in state], grad)
            for y in ("qdd", "nu", "tau_cmd"):
                self.assertEqual(getattr(gpu, y).device.type, "cuda")
                torch.testing.assert_close(getattr(gpu, y).cpu(), getattr(cpu, y), msg=f"{y}, grad={grad}")
            self.assertTrue(torch.equal(gpu.status.cpu(), cpu.status), f"status, grad={grad}")
            self.assertEqual(gpu.status.dtype, torch.int64)
            self.assertEqual(len(gpu_grads), len(cpu_grads))
            for got, want in zip(gpu_grads, cpu_grads):
                self.assertEqual(got.device.type, "cuda")
                torch.testing.assert_close(got.cpu(), want)


class PandaNc6Fixed(OnTheGpu, test_torch.PandaNc6Fixed):
    pass


class PandaNc0(OnTheGpu, test_torch.PandaNc0):
    pass


class CoupledJoints(OnTheGpu, test_torch.CoupledJoints):
    pass


class FloatingBase(OnTheGpu, test_torch.DerivativeSceneTest, unittest.TestCase):
    STEM = "planar_floating_derivatives"

    def test_float32(self):
        """float32 tensors on the GPU go to the f32 kernels. Their forward and backward are judged by
        the f64 results on the CPU: the GPU's float error within 10 times the CPU's float error plus
        8 float eps of the largest value (two float evaluations of the same expressions, contracted
        differently: errors of one size; the margin for the batch's worst state, the floor for a CPU
        error that happens to vanish)."""
        state = random_state(self.m, self.generator, (64,), driver_scale=self.DRIVER_SCALE)
        reference, reference_grads = self.solve(state, True)
        cpu, cpu_grads = self.solve(state, True, torch.float32)
        gpu, gpu_grads = self.solve([t.to(DEVICE) for t in state], True, torch.float32)
        self.assertEqual(gpu.qdd.dtype, torch.float32)
        self.assertTrue(torch.equal(gpu.status.cpu(), cpu.status))
        eps = torch.finfo(torch.float32).eps
        for got, want, exact in zip([gpu.qdd, *gpu_grads], [cpu.qdd, *cpu_grads], [reference.qdd, *reference_grads]):
            gpu_error = (got.cpu().double() - exact).abs().max()
            cpu_error = (want.double() - exact).abs().max()
            self.assertLessEqual(gpu_error, 10 * cpu_error + 8 * eps * exact.abs().max())


class Layer(unittest.TestCase):
    """The layer's handling of CUDA tensors, on panda_lean_nc6_fixed_derivatives, planar_floating_derivatives
    (which checks its inputs) and panda_nc6 (without kernels)."""

    @classmethod
    def setUpClass(cls):
        import panda_lean_nc6_fixed_derivatives
        import panda_nc6
        import planar_floating_derivatives
        cls.m, cls.checking, cls.without = panda_lean_nc6_fixed_derivatives, planar_floating_derivatives, panda_nc6
        cls.generator = torch.Generator().manual_seed(SEED)

    def state(self, batch, module=None):
        return [t.to(DEVICE) for t in random_state(module or self.m, self.generator, batch)]

    def test_modules_say_whether_they_have_kernels(self):
        self.assertTrue(self.m.cuda)
        self.assertFalse(self.without.cuda)

    def test_many_states(self):
        """100 000 states, one launch: the GPU's against the CPU's."""
        state = random_state(self.m, self.generator, (100_000,))
        cpu = self.m.torch.solve(*state)
        gpu = self.m.torch.solve(*[t.to(DEVICE) for t in state])
        self.assertTrue(torch.equal(gpu.status.cpu(), cpu.status))
        for y in ("qdd", "nu", "tau_cmd"):
            torch.testing.assert_close(getattr(gpu, y).cpu(), getattr(cpu, y), msg=y)

    def test_broadcast_and_non_contiguous_arguments(self):
        """A 1-D argument shared by every row, a non-contiguous one: the results of the same states as
        contiguous rows, bit for bit (one kernel, the same values in)."""
        q, qd, drivers, beta = self.state((4,))
        shared = self.m.torch.solve(q[1], qd, drivers, beta)
        rows = self.m.torch.solve(q[1].expand(4, -1).contiguous(), qd, drivers, beta)
        self.assertTrue(torch.equal(shared.qdd, rows.qdd))
        wide = torch.stack([qd, torch.zeros_like(qd)], -1)
        strided = self.m.torch.solve(q, wide[..., 0], drivers, beta)
        self.assertFalse(wide[..., 0].is_contiguous())
        self.assertTrue(torch.equal(strided.qdd, self.m.torch.solve(q, qd, drivers, beta).qdd))

    def test_a_nan_state_is_flagged_and_raised_on_request(self):
        m = self.checking
        q, qd, drivers, beta = self.state((3,), m)
        q[1, -1] = float("nan")
        s = m.torch.solve(q, qd, drivers, beta)
        self.assertEqual([bool(v & m.Status.not_finite) for v in s.status.tolist()], [False, True, False])
        for grad in (False, True):  # the solve kernel, the derivatives kernel
            with self.assertRaises(m.SolverStatusError) as raised:
                m.torch.solve(q, qd.clone().requires_grad_(grad), drivers, beta, raise_on_status=m.Status.not_finite)
            self.assertEqual(raised.exception.index, 1)
            self.assertRegex(str(raised.exception), r"_cuda \(policy original\): status \d+ \(.*not_finite.*\) at row 1 "
                                                     r"\(1 of 3 rows flagged\)")

    def test_bad_devices(self):
        q, qd, drivers, beta = self.state((2,))
        with self.assertRaisesRegex(ValueError, r"qd is on cpu, q on cuda:0: give every argument one device"):
            self.m.torch.solve(q, qd.cpu(), drivers, beta)
        with self.assertRaisesRegex(ValueError, r"panda_nc6\.torch\.solve: q is on cuda:0; this module has no CUDA "
                                                r"kernels \(built without its solver's CUDA library"):
            self.without.torch.solve(*self.state((2,), self.without))


if __name__ == "__main__":
    if not torch.cuda.is_available():
        sys.exit(f"test_torch_cuda.py: no CUDA device for torch {torch.__version__}: nothing to test here")
    print(f"torch {torch.__version__}, {torch.cuda.get_device_name()}")
    unittest.main(verbosity=2)
