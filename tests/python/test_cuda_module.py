"""A scene module built with its solver's CUDA library (cmake/SweepgenAddPythonModule.cmake,
python/module_cuda.cu), on any machine: run by ctest (tests/python/CMakeLists.txt,
python_cuda_module) with SWEEPGEN_PYTHON_CUDA_MODULES the modules built so. Each:
  - loads, says it has kernels (`cuda`) and has _solve_cuda in each scalar variant;
  - links lib<module>_cuda.so, which exports one symbol, sweepgen_cuda_tables_<module> (its host
    copy of the solver's functions and the CUDA runtime stay hidden);
  - its launches check their arguments before they reach CUDA (a policy, n, a null address), and
    with n = 0 launch nothing;
  - without an NVIDIA driver (no /dev/nvidiactl), a launch raises RuntimeError with CUDA's reason;
    with one, that case is skipped, counted and printed (tests/python/cuda/run.sh runs the kernels).
The kernels' results: tests/python/cuda/test_torch_cuda.py, on a GPU.
"""

import importlib
import os
import subprocess
import unittest

MODULES = [m for m in os.environ.get("SWEEPGEN_PYTHON_CUDA_MODULES", "").split(",") if m]
HAS_DRIVER = os.path.exists("/dev/nvidiactl")
skipped = []


class CudaModule(unittest.TestCase):
    def test_modules_were_given(self):
        self.assertTrue(MODULES, "SWEEPGEN_PYTHON_CUDA_MODULES is empty")

    def test_each_module(self):
        for name in MODULES:
            with self.subTest(module=name):
                m = importlib.import_module(name)
                self.assertTrue(m.cuda)
                for scalar in m.scalars:
                    variant = getattr(m, scalar)
                    self.assertTrue(hasattr(variant, "_solve_cuda"), scalar)
                    self.check_launch(name, scalar, variant)
                library = os.path.join(os.path.dirname(m.__file__), f"lib{name}_cuda.so")
                self.assertTrue(os.path.exists(library), library)
                symbols = subprocess.run(["nm", "-D", "--defined-only", library], capture_output=True, text=True,
                                         check=True).stdout.split()
                exported = [s for s in symbols[2::3]]  # nm's lines: address, type, name
                self.assertEqual(exported, [f"sweepgen_cuda_tables_{name}"])

    def check_launch(self, name, scalar, variant):
        launch = variant._solve_cuda
        with self.assertRaisesRegex(ValueError, r"'fastest' is not a policy of this scene"):
            launch(1, 8, 8, 0, policy="fastest")
        with self.assertRaisesRegex(ValueError, r"n = -1 states is not within 0 \.\. 2\^31 - 1"):
            launch(-1, 8, 8, 0)
        with self.assertRaisesRegex(ValueError, r"a null device address"):
            launch(1, 0, 8, 0)
        launch(0, 0, 0, 0)  # no states: nothing launched, no error
        if HAS_DRIVER:
            skipped.append(f"{name}.{scalar}: a launch without a GPU (this machine has an NVIDIA driver)")
            return
        with self.assertRaisesRegex(RuntimeError, rf"{name}\.{scalar}\._solve_cuda \(policy \w+\): CUDA: \S"):
            launch(1, 8, 8, 0)


if __name__ == "__main__":
    program = unittest.main(verbosity=2, exit=False)
    print(f"skipped cases: {len(skipped)} (at most one per module and scalar)")
    for case in skipped:
        print(f"  skipped: {case}")
    raise SystemExit(0 if program.result.wasSuccessful() else 1)
