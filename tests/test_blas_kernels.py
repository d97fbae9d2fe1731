"""The checks that depend on floating-point solvers hold under every OpenBLAS kernel.

OpenBLAS picks its kernel for the CPU at load time (numpy's bundled copy and Debian's, which CHOLMOD
uses, both honour OPENBLAS_CORETYPE); the kernels sum in different orders, so a test that compares
solver output bit for bit passes on one CPU and fails on another. Each case here runs the checks in CHECKS
in a child process under one forced kernel. A kernel needs its instruction set:
Prescott needs SSE3 (`pni` in /proc/cpuinfo), SkylakeX and Cooperlake need AVX-512 (Cooperlake also AVX512-BF16), Haswell and Zen need AVX2 and FMA.
Where this CPU lacks them, the child is expected to die of SIGILL (checked, so that a kernel which
should run but crashes still fails), and the case says so instead of passing silently.
"""
import os
import pathlib
import signal
import subprocess
import sys
import warnings

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
KERNELS = {"Prescott": {"pni"}, "Sandybridge": {"avx"}, "Haswell": {"avx2", "fma"},
           "SkylakeX": {"avx512f", "avx512dq", "avx512bw", "avx512vl"},
           "Cooperlake": {"avx512f", "avx512dq", "avx512bw", "avx512vl", "avx512_bf16"}, "Zen": {"avx2", "fma"}}
# the floating-point-sensitive checks: the Laplacian golden records (CHOLMOD on BLAS) and the feature
# invariance (PCA and eigen-decompositions on LAPACK)
CHECKS = ["tests/test_laplacian_golden.py", "tests/test_steganalysis_features.py::test_invariance_every_component"]
PROBE = "import numpy as np; a = np.random.default_rng(0).random((400, 400)); np.linalg.eigh(a @ a.T); print('ok')"


def _cpu_flags() -> set:
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("flags"):
                return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


def _env(kernel: str) -> dict:
    return {**os.environ, "OPENBLAS_CORETYPE": kernel, "OPENBLAS_VERBOSE": "0"}


@pytest.mark.parametrize("kernel", list(KERNELS))
def test_checks_hold_under_kernel(kernel):
    flags = _cpu_flags()
    supported = KERNELS[kernel] <= flags if flags else True
    probe = subprocess.run([sys.executable, "-c", PROBE], env=_env(kernel), capture_output=True, text=True,
                           timeout=120)
    if not supported:
        assert probe.returncode == -signal.SIGILL, (
            f"{kernel}: this CPU lacks {sorted(KERNELS[kernel] - flags)}, yet the kernel did not die of SIGILL "
            f"(rc {probe.returncode}): {probe.stderr[-500:]}")
        warnings.warn(f"OpenBLAS kernel {kernel} cannot run on this CPU (no {sorted(KERNELS[kernel] - flags)}): "
                      "its checks run only on a CPU that has them")
        return
    assert probe.returncode == 0 and probe.stdout.strip() == "ok", (kernel, probe.returncode, probe.stderr[-500:])
    r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *CHECKS],
                       env=_env(kernel), cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, f"under OPENBLAS_CORETYPE={kernel}:\n{r.stdout[-3000:]}\n{r.stderr[-1000:]}"
