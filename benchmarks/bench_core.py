"""Speed of the core kinematics (prints a table; not a test).

Run:  python benchmarks/bench_core.py [--quick]

Single-configuration calls are timed in CPU time of this process and divided by the
yardstick of ``yardstick.py`` (a naive NumPy DH forward kinematics, timed in the same
run). Targets (UR10 unless noted):
  single FK <= 0.3 yardstick, single geometric Jacobian <= 0.5 yardstick,
  batched FK <= 0.3 us/config and batched Jacobian <= 1 us/config at N = 100,000,
  symbolic FK + Jacobian of the 7-DOF Baxter derived and simplified <= 20 s.
"""

from __future__ import annotations

import sys
import time
import timeit

import numpy as np

from yardstick import cpu_per_call, yardstick_seconds

from robokin.models import baxter_left, eth_leg, ur10


def per_call(fn, number: int, repeat: int = 9) -> float:
    """Best-of-``repeat`` seconds per call."""
    return min(timeit.repeat(fn, number=number, repeat=repeat)) / number


def main(quick: bool = False) -> list[tuple[str, float, str, float]]:
    rows: list[tuple[str, float, str, float]] = []
    robot = ur10()
    q = robot.random_configurations(1, seed=0)[0]
    n_single = 2000 if quick else 20000
    yard = yardstick_seconds()
    rows.append(("yardstick: naive NumPy DH fk (UR10)", yard * 1e6, "us", float("nan")))
    singles = {
        "UR10 fk single": (lambda: robot.fk(q), 0.3),
        "UR10 fk single check=False": (lambda: robot.fk(q, check=False), 0.3),
        "UR10 jacobian single": (lambda: robot.jacobian(q), 0.5),
        "UR10 fk_and_jacobian single": (lambda: robot.fk_and_jacobian(q), 0.5),
        "UR10 frames single": (lambda: robot.frames(q), float("nan")),
    }
    for name, (fn, target) in singles.items():
        rows.append((name, cpu_per_call(fn, n_single) / yard, "yardsticks", target))
    N = 10_000 if quick else 100_000
    Q = robot.random_configurations(N, seed=1)
    rows.append((f"UR10 fk batch N={N}", per_call(lambda: robot.fk(Q), 1, 9) / N * 1e6, "us/config", 0.3))
    rows.append((f"UR10 jacobian batch N={N}",
                 per_call(lambda: robot.jacobian(Q), 1, 9) / N * 1e6, "us/config", 1.0))
    rows.append((f"UR10 fk_and_jacobian batch N={N}",
                 per_call(lambda: robot.fk_and_jacobian(Q), 1, 9) / N * 1e6, "us/config", float("nan")))
    rows.append((f"UR10 frames batch N={N}",
                 per_call(lambda: robot.frames(Q), 1, 5) / N * 1e6, "us/config", float("nan")))
    f = robot.lambdify_fk()
    rows.append((f"UR10 lambdify_fk batch N={N}", per_call(lambda: f(Q), 1, 9) / N * 1e6, "us/config",
                 float("nan")))
    leg = eth_leg()
    ql = leg.random_configurations(1, seed=0)[0]
    rows.append(("ETH leg jacobian single", cpu_per_call(lambda: leg.jacobian(ql), n_single) / yard, "yardsticks",
                 float("nan")))
    bax = baxter_left()
    qb = bax.random_configurations(1, seed=0)[0]
    rows.append(("Baxter fk single", cpu_per_call(lambda: bax.fk(qb), n_single) / yard, "yardsticks", 0.3))
    rows.append(("Baxter jacobian single", cpu_per_call(lambda: bax.jacobian(qb), n_single) / yard, "yardsticks",
                 0.5))
    t0 = time.perf_counter()
    fresh = baxter_left()
    s = fresh.symbols()
    fresh.fk(s)
    fresh.jacobian(s)
    rows.append(("Baxter symbolic fk + jacobian", time.perf_counter() - t0, "s", 20.0))
    return rows


def print_table(rows) -> None:
    import os

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"numpy {np.__version__}, {os.cpu_count()} CPUs, load average {load:.2f} "
          "(times are best of several repeats; other processes inflate them)")
    print(f"{'benchmark':40s} {'time':>10s} {'unit':10s} {'target':>8s}  ok")
    print("-" * 76)
    for name, t, unit, target in rows:
        ok = "" if target != target else ("yes" if t <= target else "NO")
        tgt = "" if target != target else f"{target:g}"
        print(f"{name:40s} {t:10.3f} {unit:10s} {tgt:>8s}  {ok}")


if __name__ == "__main__":
    print_table(main(quick="--quick" in sys.argv))
