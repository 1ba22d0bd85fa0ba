"""The same bits on every CPU: a quasi-periodic episode, a transient and a field episode, the
reward-map cell of issue 29 and a static equilibrium (``probe.py``) give bit-identical final
states, observations and returns under every dispatch setting this machine can emulate:

* glibc's libm code paths (``GLIBC_TUNABLES=glibc.cpu.hwcaps=-...``: the non-FMA and SSE2
  variants of exp/log/pow/sin/cos, as on an older or another vendor's CPU);
* numba's target CPU (``NUMBA_CPU_NAME=generic`` against the host's), compiled afresh;
* NumPy's SIMD dispatch (``NPY_DISABLE_CPU_FEATURES``) and OpenBLAS's kernels
  (``OPENBLAS_CORETYPE``).

On the kernel before the portable one (glibc's libm in the Hertz constants, the ball angles and
the waviness; LAPACK in the features and the equilibrium) the libm mask alone moved the
quasi-periodic episode's return from -526.49 to -561.10 (issue 29's closing note).

The generic-CPU run compiles in an empty cache, so it can also read numba's LLVM IR: the
compiled code of ``bearing_gym`` may call no floating-point function but ``sqrt`` (correctly
rounded by IEEE 754 on every CPU) and ``fabs``.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

PROBE = Path(__file__).with_name("probe.py")
ROOT = Path(__file__).resolve().parents[2]
ALLOWED_FLOAT_FUNCTIONS = {"sqrt", "llvm.sqrt.f64", "llvm.fabs.f64"}
LIBM_MASK = "glibc.cpu.hwcaps=-FMA,-AVX2,-AVX512F"
LIBM_MASK_SSE2 = "glibc.cpu.hwcaps=-SSE4_1,-SSE4_2,-AVX,-AVX2,-FMA,-AVX512F"


def _numpy_dispatch_features() -> str:
    """The SIMD features NumPy dispatches to on this CPU beyond its baseline (disabling a
    baseline feature is an error)."""
    from numpy._core._multiarray_umath import __cpu_baseline__, __cpu_dispatch__, __cpu_features__
    extra = [f for f in __cpu_dispatch__ if __cpu_features__.get(f) and f not in __cpu_baseline__]
    return " ".join(extra)


def _run(extra_env: dict[str, str], *args: str) -> subprocess.Popen:
    env = {k: v for k, v in os.environ.items()
           if k not in ("GLIBC_TUNABLES", "NUMBA_CPU_NAME", "NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE")}
    env.update(extra_env)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.Popen([sys.executable, str(PROBE), *args], env=env, cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _result(proc: subprocess.Popen, label: str) -> dict:
    out, err = proc.communicate(timeout=900)
    assert proc.returncode == 0, f"probe under {label} failed:\n{err[-3000:]}"
    return json.loads(out.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict[str, dict]:
    if platform.machine().lower() not in ("x86_64", "amd64"):
        pytest.skip("the dispatch settings emulated here (glibc hwcaps, OpenBLAS core types) are x86-64's")
    fresh_cache = tmp_path_factory.mktemp("numba_generic")
    settings = {
        "host": {},
        "libm without FMA/AVX2/AVX-512": {"GLIBC_TUNABLES": LIBM_MASK},
        "libm SSE2 only": {"GLIBC_TUNABLES": LIBM_MASK_SSE2},
        "NumPy baseline SIMD, OpenBLAS Prescott": {"NPY_DISABLE_CPU_FEATURES": _numpy_dispatch_features(),
                                                   "OPENBLAS_CORETYPE": "Prescott"},
    }
    # the fresh compile takes the longest: start it first, beside the others (2 cores)
    generic = _run({"NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(fresh_cache),
                    "GLIBC_TUNABLES": LIBM_MASK}, "--llvm")
    results = {}
    for label, extra in settings.items():
        results[label] = _result(_run(extra), label)
    results["numba generic CPU (fresh compile)"] = _result(generic, "NUMBA_CPU_NAME=generic")
    return results


def test_probe_exercises_quasi_periodic_motion(runs):
    qp = runs["host"]["quasi_periodic"]
    assert qp["steps"] == 60
    # vibration first: a quasi-periodic interval costs at least 1, so 60 of them at least 60
    assert qp["return"] < -60.0, qp


@pytest.mark.parametrize("label", ["libm without FMA/AVX2/AVX-512", "libm SSE2 only",
                                   "NumPy baseline SIMD, OpenBLAS Prescott",
                                   "numba generic CPU (fresh compile)"])
def test_bit_identical_under_every_setting(runs, label):
    host = runs["host"]
    other = {k: v for k, v in runs[label].items() if k != "llvm_float_functions"}
    assert other == host, f"{label} differs from the host run"


def test_compiled_kernels_call_no_libm_or_lapack(runs):
    found = runs["numba generic CPU (fresh compile)"]["llvm_float_functions"]
    assert found, "the scan saw no compiled function at all"
    assert "llvm.sqrt.f64" in found or "sqrt" in found            # the scan sees the kernels
    bad = {fn: users for fn, users in found.items() if fn not in ALLOWED_FLOAT_FUNCTIONS}
    assert not bad, f"compiled code calls non-portable floating-point functions: {bad}"
