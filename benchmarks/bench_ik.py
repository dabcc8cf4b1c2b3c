"""Benchmark the IK solvers on random reachable 6D poses of the UR10 and Baxter.

Targets are the forward kinematics of seeded random configurations within the
joint limits.  For each method: single solves with ``solve_ik`` (default
options: initial guess = middle of the limits, 20 seeded restarts, LM polish
of failures, tolerance 1e-6 m / 1e-6 rad; the methods other than "lm" run
without the LM polish so that each is measured alone) and one batched call
with ``solve_ik_batch`` on all targets.

Usage::

    python benchmarks/bench_ik.py              # 1000 targets for "lm", 200 for the others
    python benchmarks/bench_ik.py --n 300 --robots ur10

Prints a Markdown table: success rate, median wall and CPU time per solve
(CPU time of this process: less sensitive to other load on the machine),
the median CPU time as a multiple of the yardstick of ``yardstick.py`` (a naive
NumPy DH forward kinematics of the UR10, timed in the same run before each method: the
ratio compares runs on a loaded or a different machine; goal for "lm": at most 15), mean wall time,
mean iterations (summed over attempts), and the batched success rate and wall
time per target. A last table times the AR-601 leg's
closed-form inverse kinematics (all eight solutions) against ``solve_ik`` on the
same poses (Chapter 6 compares their work; the seconds are measured here).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from yardstick import yardstick_seconds

import robokin.models as models
from robokin.motion import solve_ik, solve_ik_batch

METHODS = {
    "lm": {},
    "pinv": {},
    "dls": {},
    "dls (manipulability)": {"adaptive": "manipulability"},
    "weighted": {"weights": "ramp"},
    "nullspace": {},
    "transpose": {"max_iterations": 300},
}


def _options(name: str, n: int) -> tuple[str, dict]:
    opts = dict(METHODS[name])
    if name != "lm":
        opts["polish"] = False  # each method alone (the LM polish would rescue its failures)
    if opts.get("weights") == "ramp":
        opts["weights"] = np.linspace(1.0, 2.0, n)
    return name.split(" ")[0], opts


def bench(robot: str, n_lm: int, n_other: int, methods: list[str]) -> list[dict]:
    chain = getattr(models, robot)()
    rows = []
    for name in methods:
        N = n_lm if name == "lm" else n_other
        Q = chain.random_configurations(N, seed=12345)
        T = chain.fk(Q)
        method, opts = _options(name, chain.n)
        solve_ik(chain, T[0], method=method, **opts)  # warm-up (engine caches)
        times, cpu, ok, its = np.empty(N), np.empty(N), np.empty(N, bool), np.empty(N)
        yard = yardstick_seconds()
        for i in range(N):
            t0, c0 = time.perf_counter(), time.process_time()
            r = solve_ik(chain, T[i], method=method, record_history=False, **opts)
            times[i] = time.perf_counter() - t0
            cpu[i] = time.process_time() - c0
            ok[i], its[i] = r.success, r.iterations
        t0 = time.perf_counter()
        rb = solve_ik_batch(chain, T, method=method, **opts)
        tb = (time.perf_counter() - t0) / N
        rows.append({
            "robot": robot, "method": name, "N": N, "success": ok.mean(), "median_ms": 1e3 * np.median(times),
            "mean_ms": 1e3 * times.mean(), "median_cpu_ms": 1e3 * np.median(cpu),
            "yardsticks": np.median(cpu) / yard, "iterations": its.mean(),
            "batch_success": rb.success.mean(),
            "batch_us": 1e6 * tb,
        })
        r = rows[-1]
        print(f"| {robot} | {name} | {N} | {100 * r['success']:.1f} % | {r['median_ms']:.3f} "
              f"| {r['median_cpu_ms']:.3f} | {r['yardsticks']:.1f} | {r['mean_ms']:.3f} "
              f"| {r['iterations']:.1f} | {100 * r['batch_success']:.1f} % | {r['batch_us']:.0f} |", flush=True)
    return rows


def bench_ar601(n: int) -> None:
    """Closed form vs numerical IK of the AR-601 leg on n random reachable foot poses."""
    from robokin.models.ar601_ik import ar601_leg_ik

    leg = models.ar601_leg()
    T = leg.fk(leg.random_configurations(n, seed=5))
    q_home = np.array([0.0, 0.0, 0.3, -0.6, 0.0, 0.3])
    ar601_leg_ik(T[0])
    solve_ik(leg, T[0], q0=q_home)  # warm-up
    rows = {"closed form (8 solutions)": lambda pose: ar601_leg_ik(pose),
            "solve_ik from Q_HOME (1 solution)": lambda pose: solve_ik(leg, pose, q0=q_home, tol=1e-10,
                                                                        record_history=False)}
    print()
    print(f"AR-601 leg: {n} random reachable foot poses, wall time per pose")
    print("| solver | median ms | 90th percentile ms | max ms |")
    print("|---|---|---|---|")
    for name, solve in rows.items():
        times = np.empty(n)
        for i in range(n):
            t0 = time.perf_counter()
            solve(T[i])
            times[i] = time.perf_counter() - t0
        print(f"| {name} | {1e3 * np.median(times):.3f} | {1e3 * np.percentile(times, 90):.3f} "
              f"| {1e3 * times.max():.3f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="targets for the default method 'lm'")
    ap.add_argument("--n-other", type=int, default=200, help="targets for the other methods")
    ap.add_argument("--robots", nargs="+", default=["ur10", "baxter_left"])
    ap.add_argument("--methods", nargs="+", default=list(METHODS), choices=list(METHODS))
    ap.add_argument("--batch", type=int, default=1000, help="targets of the extra 'lm' batch timing (0: skip)")
    ap.add_argument("--ar601", type=int, default=100, help="poses of the AR-601 closed-form table (0: skip)")
    args = ap.parse_args()
    print("| robot | method | N | success | median ms/solve | median CPU ms/solve | median CPU / naive DH fk "
          "| mean ms/solve | mean iterations | batch success | batch µs/target |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for robot in args.robots:
        bench(robot, args.n, args.n_other, args.methods)
    if args.batch:
        bench_batch(args.robots, args.batch)
    if args.ar601:
        bench_ar601(args.ar601)


def bench_batch(robots: list[str], n: int) -> None:
    """The default method batched on ``n`` random reachable targets per robot."""
    print()
    print(f"Batched 'lm' on {n} targets (best of 5 runs; wall and CPU time of this process):")
    for robot in robots:
        chain = getattr(models, robot)()
        T = chain.fk(chain.random_configurations(n, seed=777))
        best, best_cpu = np.inf, np.inf
        for _ in range(5):
            t0, c0 = time.perf_counter(), time.process_time()
            rb = solve_ik_batch(chain, T)
            best = min(best, time.perf_counter() - t0)
            best_cpu = min(best_cpu, time.process_time() - c0)
        print(f"  {robot}: {1e6 * best / n:.1f} µs/target wall, {1e6 * best_cpu / n:.1f} µs/target "
              f"CPU, success {100 * rb.success.mean():.2f} %, mean iterations {rb.iterations.mean():.1f}")


if __name__ == "__main__":
    main()
