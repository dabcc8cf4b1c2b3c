"""Seeded IK cases whose results are recorded bit for bit (no tests here).

Used by ``tests/test_ik_refactor_identity.py``: every case is one call of
:func:`robokin.motion.solve_ik` (or :func:`~robokin.motion.solve_ik_batch`)
with arguments drawn from a fixed seed -- methods and their options, robots
(planar 3R with and without limits, a planar arm with a prismatic joint, the
UR10, Baxter's left arm), pose and position targets, reachable and not, masks,
tools, wrapping, step caps, restarts and the LM polish.  The result's arrays
(q, errors, every history array) and scalars are hashed with SHA-256 (compared
bit for bit on the platform that recorded them), and the outcome of every case
is stored as values too (q, success, reason: compared with :data:`Q_TOLERANCE`
on any other platform, see :func:`value_differences`).

Regenerate the golden file (only when a change of arithmetic is intended, and
say so in the commit message)::

    PYTHONPATH=. python tests/support/ik_identity_cases.py

It runs the cases twice: here, and in a child process with other SIMD kernels
of numpy and another BLAS kernel (:data:`OTHER_KERNELS`). A case whose outcome
differs between the two (beyond :data:`Q_TOLERANCE`) is *sensitive*: a last-bit
change of the arithmetic sends it elsewhere (an unreachable target, a restart,
a redundant arm drifting to another solution), so that only its digest, not its
values, can be compared.
"""

from __future__ import annotations

import hashlib
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

import robokin.models as models
from robokin.chains import Rz, SerialChain, Tx
from robokin.motion import (
    DampedLeastSquares,
    JacobianTranspose,
    LevenbergMarquardt,
    NullSpace,
    solve_ik,
    solve_ik_batch,
)
from robokin.transforms import rotation_exp, transform

GOLDEN = Path(__file__).parent.parent / "data" / "ik_identity_golden.npz"
SINGLE_CASES = 1000
BATCH_CASES = 40
#: Widest joint columns of the robots (Baxter's 7): q is stored padded with NaN to this width.
WIDTH = 7
#: Largest |q - q_recorded| (rad or m) of a case compared by value on another platform. The
#: solvers' default tolerance is 1e-6; with other SIMD and BLAS kernels, the final q of a
#: case that is not sensitive moves by 1e-15 (median) to 2e-8 (99th percentile of the
#: solved cases): a real change of the algorithm moves it by far more.
Q_TOLERANCE = 1e-6
#: Cases compared by value that may still differ on another platform (other CPUs may find
#: sensitive cases that the two kernel sets of the recording did not).
VALUE_BUDGET = 0.01
#: What the recording's second run changes: numpy's AVX-512 kernels off, OpenBLAS's Haswell kernels.
OTHER_KERNELS = {
    "OPENBLAS_CORETYPE": "Haswell",
    "NPY_DISABLE_CPU_FEATURES": " ".join([
        "AVX512F", "AVX512CD", "AVX512_SKX", "AVX512_CLX", "AVX512_CNL", "AVX512_ICL", "AVX512_SPR",
        "AVX512BW", "AVX512DQ", "AVX512VL", "AVX512IFMA", "AVX512VBMI", "AVX512VBMI2", "AVX512BITALG",
        "AVX512VPOPCNTDQ", "AVX512VNNI", "AVX512BF16", "AVX512FP16"]),
}


def _planar_3r(limited: bool) -> SerialChain:
    limits = [[-2.5, 2.5], [-2.0, 2.0], [-2.0, 2.0]] if limited else None
    return SerialChain([Rz("q1"), Tx(1.0), Rz("q2"), Tx(0.8), Rz("q3"), Tx(0.5)],
                       limits=limits, name="planar_3r")


def _planar_rpr() -> SerialChain:
    """Revolute, prismatic (0.2 .. 1.0 m along x), revolute: a planar arm with a slider."""
    return SerialChain([Rz("q1"), Tx("q2"), Rz("q3"), Tx(0.4)],
                       limits=[[-3.0, 3.0], [0.2, 1.0], [-2.5, 2.5]], name="planar_rpr")


def robots() -> dict[str, Any]:
    return {
        "planar_3r": _planar_3r(True),
        "planar_3r_free": _planar_3r(False),
        "planar_rpr": _planar_rpr(),
        "ur10": models.ur10(),
        "baxter_left": models.baxter_left(),
    }


_ROBOT_WEIGHTS = {"planar_3r": 0.2, "planar_3r_free": 0.1, "planar_rpr": 0.1, "ur10": 0.35, "baxter_left": 0.25}
_METHODS = ("lm", "pinv", "transpose", "weighted", "dls", "dls_manip", "dls_sv", "dls_error", "dls0",
            "nullspace", "nullspace_manip", "nullspace_fn", "lm_weights", "transpose_gain")


def _random_config(rng: np.random.Generator, chain: Any) -> np.ndarray:
    lim = np.asarray(chain.limits, dtype=float) if chain.limits is not None else None
    if lim is None:
        return rng.uniform(-np.pi, np.pi, chain.n)
    lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -np.pi)
    hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], np.pi)
    return lo + (hi - lo) * rng.random(chain.n)


def _method(rng: np.random.Generator, name: str, n: int) -> tuple[Any, dict[str, Any]]:
    """(method argument, options) for a method label."""
    if name == "lm":
        return "lm", {}
    if name == "pinv":
        return "pinv", ({"gain": 0.7} if rng.random() < 0.3 else {})
    if name == "transpose":
        return "transpose", {"max_iterations": int(rng.integers(20, 120))}
    if name == "transpose_gain":
        return JacobianTranspose(gain=0.5), {"max_iterations": 60}
    if name == "weighted":
        return "weighted", {"weights": np.linspace(1.0, 3.0, n)}
    if name == "dls":
        return "dls", {"damping": float(rng.choice([0.01, 0.05, 0.2]))}
    if name == "dls_manip":
        return DampedLeastSquares(damping=0.1, adaptive="manipulability"), {}
    if name == "dls_sv":
        return "dls", {"damping": 0.1, "adaptive": "singular_value"}
    if name == "dls_error":
        return "dls", {"adaptive": "error"}
    if name == "dls0":
        return "dls", {"damping": 0.0}
    if name == "nullspace":
        return "nullspace", {}
    if name == "nullspace_manip":
        return NullSpace(objective="manipulability", gain=0.5), {"max_iterations": 40}
    if name == "nullspace_fn":
        return NullSpace(objective=lambda q: -0.1 * q, gain=2.0), {}
    if name == "lm_weights":
        return LevenbergMarquardt(error_weights=[1.0, 1.0, 1.0, 0.5, 0.5, 0.5], error_damping=1.0), {}
    raise KeyError(name)


def _target(rng: np.random.Generator, chain: Any, planar: bool, position: bool) -> np.ndarray:
    q = _random_config(rng, chain)
    T = chain.fk(q)
    if rng.random() < 0.15:  # out of reach (scaled position), or a perturbed orientation
        T = T.copy()
        T[:3, 3] *= 1.0 + rng.uniform(0.3, 1.0)
    elif rng.random() < 0.15 and not planar:
        T = T @ transform(rotation_exp(rng.normal(size=3) * 0.3), np.zeros(3))
    return T[:3, 3].copy() if position else T


def single_cases(count: int = SINGLE_CASES, seed: int = 20261124) -> list[dict[str, Any]]:
    """``count`` keyword sets for ``solve_ik`` (each with ``robot`` naming the chain)."""
    rng = np.random.default_rng(seed)
    chains = robots()
    names = list(_ROBOT_WEIGHTS)
    p = np.array(list(_ROBOT_WEIGHTS.values()))
    cases = []
    for _ in range(count):
        robot = str(rng.choice(names, p=p / p.sum()))
        chain = chains[robot]
        planar = robot.startswith("planar")
        method_name = str(rng.choice(_METHODS))
        method, options = _method(rng, method_name, chain.n)
        position = planar or rng.random() < 0.25
        kwargs: dict[str, Any] = {"method": method, **options}
        kwargs["target"] = _target(rng, chain, planar, position)
        if planar:
            kwargs["mask"] = [True, True, False, False, False, False]
        elif not position and rng.random() < 0.15:
            kwargs["mask"] = [True, True, True, False, False, True]
        if rng.random() < 0.6:
            kwargs["q0"] = _random_config(rng, chain)
        kwargs["restarts"] = int(rng.choice([0, 0, 0, 1, 3]))
        kwargs["polish"] = bool(rng.random() < 0.5)
        kwargs["record_history"] = bool(rng.random() < 0.8)
        if rng.random() < 0.2:
            kwargs["max_iterations"] = int(rng.integers(1, 40))
        if rng.random() < 0.15:
            kwargs["max_step"] = float(rng.choice([0.05, 0.3]))
        if rng.random() < 0.2:
            kwargs["wrap"] = bool(rng.random() < 0.5)
        if rng.random() < 0.1:
            kwargs["tol"] = (1e-4, 1e-3)
        if rng.random() < 0.1:
            kwargs["stall_iterations"], kwargs["stall_tolerance"] = 5, 0.1
        if rng.random() < 0.05:
            kwargs["seed"] = int(rng.integers(1, 1000))
        if not planar and rng.random() < 0.15:
            kwargs["tool"] = transform(rotation_exp([0.0, 0.3, 0.0]), [0.0, 0.05, 0.12])
        cases.append({"robot": robot, "label": method_name, **kwargs})
    return cases


def batch_cases(count: int = BATCH_CASES, seed: int = 777) -> list[dict[str, Any]]:
    """``count`` keyword sets for ``solve_ik_batch`` (targets stacked)."""
    rng = np.random.default_rng(seed)
    chains = robots()
    cases = []
    for _ in range(count):
        robot = str(rng.choice(["planar_3r", "ur10", "baxter_left"]))
        chain = chains[robot]
        planar = robot.startswith("planar")
        method_name = str(rng.choice(["lm", "lm", "pinv", "dls", "nullspace", "transpose", "weighted"]))
        method, options = _method(rng, method_name, chain.n)
        size = int(rng.integers(0, 12))
        position = planar or rng.random() < 0.3
        targets = np.array([_target(rng, chain, planar, position) for _ in range(size)])
        if size == 0:
            targets = np.zeros((0, 3) if position else (0, 4, 4))
        kwargs: dict[str, Any] = {"method": method, **options, "targets": targets}
        if planar:
            kwargs["mask"] = [True, True, False, False, False, False]
        kwargs["restarts"] = int(rng.choice([0, 2, 5]))
        kwargs["polish"] = bool(rng.random() < 0.6)
        if rng.random() < 0.2:
            kwargs["max_step"] = 0.2
        if rng.random() < 0.2:
            kwargs["wrap"] = True
        cases.append({"robot": robot, "label": method_name, **kwargs})
    return cases


def _hash_arrays(parts: list[Any]) -> bytes:
    h = hashlib.sha256()
    for part in parts:
        a = np.ascontiguousarray(np.asarray(part))
        if a.dtype.kind == "U":
            a = np.char.encode(a, "utf-8")
        h.update(str(a.dtype).encode() + str(a.shape).encode())
        h.update(a.tobytes())
    return h.digest()


def digest_single(res: Any) -> bytes:
    """SHA-256 of every field of an IKResult, its history arrays included."""
    parts = [res.q, res.errors, res.success, res.iterations, res.reason, res.attempts,
             res.position_error, res.orientation_error, res.method]
    if res.history is not None:
        h = res.history
        parts += [h.q, h.error, h.jacobian, h.damping, h.step_size, h.attempt, h.mask, h.limits]
    return _hash_arrays(parts)


def digest_batch(res: Any) -> bytes:
    return _hash_arrays([res.q, res.errors, res.success, res.iterations, res.reason, res.attempts,
                         res.position_error, res.orientation_error, res.method])


def run_single(case: dict[str, Any], chains: dict[str, Any]) -> Any:
    kwargs = {k: v for k, v in case.items() if k not in ("robot", "label")}
    return solve_ik(chains[case["robot"]], **kwargs)


def run_batch(case: dict[str, Any], chains: dict[str, Any]) -> Any:
    kwargs = {k: v for k, v in case.items() if k not in ("robot", "label")}
    return solve_ik_batch(chains[case["robot"]], **kwargs)


def platform_fingerprint() -> str:
    """numpy and BLAS versions, machine and the CPU features numpy uses.

    Floating-point results are reproducible bit for bit only on the same
    arithmetic: another BLAS or other SIMD kernels may change last bits.
    """
    blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
    try:
        from numpy._core._multiarray_umath import (  # type: ignore[import-not-found]  # private, no stubs
            __cpu_features__ as features,
        )
    except ImportError:  # an older or newer numpy layout
        features = {}
    enabled = ",".join(sorted(k for k, v in features.items() if v))
    return f"numpy {np.__version__}; blas {blas.get('name')} {blas.get('version')}; {platform.machine()}; {enabled}"


def _padded(q: np.ndarray) -> np.ndarray:
    out = np.full(q.shape[:-1] + (WIDTH,), np.nan)
    out[..., : q.shape[-1]] = q
    return out


def outcome_values(single: list[Any], batch: list[Any]) -> dict[str, np.ndarray]:
    """q (NaN-padded to :data:`WIDTH`), success and reason of every single case and of every
    target of the batch cases (stacked in case order; ``batch_sizes`` splits them)."""
    rows = [(r.q[i], r.success[i], r.reason[i]) for r in batch for i in range(len(r))]
    return {
        "single_q": np.array([_padded(r.q) for r in single]),
        "single_success": np.array([r.success for r in single], dtype=bool),
        "single_reason": np.array([r.reason for r in single]),
        "batch_sizes": np.array([len(r) for r in batch]),
        "batch_q": np.array([_padded(q) for q, _, _ in rows]).reshape(-1, WIDTH),
        "batch_success": np.array([s for _, s, _ in rows], dtype=bool),
        "batch_reason": np.array([str(reason) for _, _, reason in rows], dtype="<U16"),
    }


def differing(recorded: dict[str, np.ndarray], values: dict[str, np.ndarray], part: str) -> np.ndarray:
    """Mask of the cases (``part`` 'single') or batch targets ('batch') whose success or reason
    differ, or whose q differs by more than :data:`Q_TOLERANCE`."""
    q_difference = np.nanmax(np.abs(recorded[f"{part}_q"] - values[f"{part}_q"]), axis=-1, initial=0.0)
    return ((recorded[f"{part}_success"] != values[f"{part}_success"])
            | (recorded[f"{part}_reason"] != values[f"{part}_reason"])
            | ~(q_difference <= Q_TOLERANCE))


def value_differences(recorded: dict[str, np.ndarray], values: dict[str, np.ndarray], part: str) -> list[int]:
    """Indices of the cases (or batch targets) that are not sensitive and differ."""
    return list(np.flatnonzero(differing(recorded, values, part) & ~recorded[f"{part}_sensitive"]))


def compute() -> dict[str, np.ndarray]:
    """Digests, iterations and outcome values of every case, as arrays."""
    chains = robots()
    single = [run_single(c, chains) for c in single_cases()]
    batch = [run_batch(c, chains) for c in batch_cases()]
    return {
        "single_digest": np.array([list(digest_single(r)) for r in single], dtype=np.uint8),
        "single_iterations": np.array([r.iterations for r in single]),
        "batch_digest": np.array([list(digest_batch(r)) for r in batch], dtype=np.uint8),
        "platform": np.array(platform_fingerprint()),
        **outcome_values(single, batch),
    }


def _compute_with_other_kernels() -> dict[str, np.ndarray]:
    """:func:`compute` in a child process with :data:`OTHER_KERNELS` set."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "other.npz"
        code = (f"import numpy as np, support.ik_identity_cases as c; np.savez({str(out)!r}, **c.compute())")
        env = {**os.environ, **OTHER_KERNELS,
               "PYTHONPATH": os.pathsep.join([str(Path(__file__).parents[1]), str(Path(__file__).parents[2])])}
        subprocess.run([sys.executable, "-c", code], env=env, check=True)
        with np.load(out) as data:
            return {k: data[k] for k in data.files}


if __name__ == "__main__":
    data = compute()
    other = _compute_with_other_kernels()
    if str(other["platform"]) == str(data["platform"]):
        raise SystemExit("the second run did not change the arithmetic's kernels: no sensitive case can be found")
    for part in ("single", "batch"):
        data[f"{part}_sensitive"] = differing(data, other, part)
    GOLDEN.parent.mkdir(exist_ok=True)
    # numpy's stub types the arrays given by name against its allow_pickle: bool
    np.savez_compressed(GOLDEN, **data)  # type: ignore[arg-type]
    print(f"wrote {GOLDEN}: {len(data['single_digest'])} single cases "
          f"({data['single_success'].mean():.0%} solved, {data['single_sensitive'].sum()} sensitive), "
          f"{len(data['batch_digest'])} batch cases ({len(data['batch_q'])} targets, "
          f"{data['batch_sensitive'].sum()} sensitive)")
