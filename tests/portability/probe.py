"""Print, as one JSON line, SHA-256 digests of everything a fixed quasi-periodic episode produces:
final physics state, every observation and every reward, plus the reward-map cell of
issue 29 (17,500 rpm / 250 N / 17 um), a static equilibrium and the settled start.

Run in a subprocess by ``tests/portability/test_portability.py`` under several libm, numba-CPU,
NumPy-dispatch and OpenBLAS settings: the digests must be identical under every one of them.
``python tests/portability/probe.py [--llvm]``. With ``--llvm`` (in a process that compiled the
kernels itself: numba shows no IR of code loaded from its cache) it also lists every external
floating-point function that the compiled code of ``bearing_gym`` declares, under
``"llvm_float_functions"``: only ``sqrt`` (correctly rounded by IEEE 754) and ``llvm.fabs`` may
appear; ``sin``, ``exp``, ``pow``, ``llvm.fma``, a LAPACK wrapper and the like may not.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(np.asarray(a, dtype=np.float64)).tobytes())
    return h.hexdigest()[:16]


def episode(tier: str, seed: int, options: dict, actions, steps: int | None = None) -> dict:
    """One episode under a fixed action sequence, or (``actions`` a policy) under a policy's
    deterministic actions for ``steps`` steps."""
    from bearing_gym.envs import BearingPreloadEnv
    env = BearingPreloadEnv(tier=tier)
    obs, info = env.reset(seed=seed, options=options)
    observations, rewards = [obs], []
    policy = None if isinstance(actions, np.ndarray) else actions
    state, start = None, np.array([True])
    for k in range(steps if policy is not None else len(actions)):
        if policy is not None:
            act, state = policy.predict(obs[None], state=state, episode_start=start)
            a, start = act[0], np.array([False])
        else:
            a = actions[k]
        obs, r, term, trunc, info = env.step(a)
        observations.append(obs)
        rewards.append(r)
        if term or trunc:
            break
    b = env.batch
    state = [b.X[0], b.V[0], b.A[0], b.scal[0], b.psi_b[0], b.ball_v[0], b.ball_out[0]]
    return {"state": digest(*state), "obs": digest(*observations), "rewards": digest(rewards),
            "return": float(np.sum(rewards)), "steps": len(rewards)}


def external_float_functions() -> dict[str, list[str]]:
    """External functions with a float argument or result (or a LAPACK/BLAS wrapper) declared by
    the LLVM IR of every compiled numba function of ``bearing_gym``, with who declares them."""
    import re

    from numba.core.registry import CPUDispatcher
    found: dict[str, set[str]] = {}
    for name, module in list(sys.modules.items()):
        if not name.startswith(("bearing_gym", "agents")):
            continue
        for attr, obj in list(vars(module).items()):
            if not isinstance(obj, CPUDispatcher) or not obj.signatures:
                continue
            for ir in obj.inspect_llvm().values():
                for line in re.findall(r"^declare .*$", ir, re.M):
                    fn = re.search(r'@"?([\w.$]+)"?\(', line).group(1)
                    if fn.startswith(("Py", "_Py")):     # the Python C API of the wrappers
                        continue
                    lapack = re.search(r"^numba_(x+|ez_)[a-z]|blas|lapack", fn)   # numba_xgesv, ...
                    
                    if lapack or re.search(r"\b(double|float|half|fp128|x86_fp80)\b", line):
                        found.setdefault(fn, set()).add(f"{name}.{attr}")
    return {fn: sorted(users) for fn, users in sorted(found.items())}


def main(quick: bool) -> dict:
    import bearing_gym
    from bearing_gym.physics import static_equilibrium
    out: dict = {}
    eq = static_equilibrium(bearing_gym.default_params(shaft_speed_rpm=17500.0, radial_load_x_n=250.0,
                                                       clearance_inner_m=17e-6, clearance_outer_m=17e-6,
                                                       axial_preload_n=300.0))
    out["equilibrium"] = digest(eq.U, eq.stiffness, eq.q_i, eq.q_o)
    n = 25 if quick else 60
    # the quasi-periodic point (17,500 rpm, 250 N, 17 um, 300 N) with race waviness, constant preload
    qp = {"shaft_speed_rpm": 17500.0, "radial_load_n": 250.0, "clearance_m": 17e-6,
          "initial_preload_n": 300.0, "waviness_amplitude_m": 0.5e-6}
    out["quasi_periodic"] = episode("stationary", 7, qp, np.full((n, 1), -1.0, np.float32))
    # a transient episode with events and a varying action; the field tier's sensor noise
    rng = np.random.default_rng(1)
    acts = rng.uniform(-1, 1, size=(n, 1)).astype(np.float32)
    out["transient"] = episode("transient", 300123, {}, acts)
    out["field"] = episode("field", 300007, {}, acts)
    # the shipped recurrent policy through the portable float64 path (no torch); absent before it
    try:
        from agents.policies.portable import PortablePolicy
    except ImportError:
        PortablePolicy = None
    if PortablePolicy is not None:
        lstm = PortablePolicy.load(ROOT / "agents" / "pretrained" / "ppo_lstm")
        out["shipped_ppo_lstm"] = episode("transient", 300004, {}, lstm, steps=n)
    if not quick:
        from bearing_gym.envs.reward_map import reward_map
        cell = reward_map(speeds_rpm=(17500.0,), radial_loads_n=(250.0,), clearances_m=(17e-6,),
                          preloads_n=(300.0, 1000.0), eccentricities_m=(10e-6,))   # issue 29's cell
        out["reward_map_cell"] = digest([[p.mean_reward, p.mean_nonsync_rms_um] for p in cell])
    return out


if __name__ == "__main__":
    result = main("--quick" in sys.argv[1:])
    if "--llvm" in sys.argv[1:]:
        result["llvm_float_functions"] = external_float_functions()
    print(json.dumps(result, sort_keys=True))
