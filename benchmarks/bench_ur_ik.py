"""Benchmark the closed-form inverse kinematics of the UR10 (all solutions) beside ``solve_ik``.

Targets are the forward kinematics of seeded random UR10 configurations. Rows:

- ``ur10_ik`` — all solutions (up to 8) of one pose, each verified by forward
  kinematics; CPU time per pose (goal: at most 3 yardsticks);
- ``ur10_ik_batch`` — the same for N poses in one call; CPU time per pose
  (goal: at most 0.1 yardstick);
- ``solve_ik`` — robokin's default numerical IK (one solution) on the same
  poses, for comparison.

Every solution is verified by the forward kinematics of the DH table inside the
solver (the product of the six DH matrices); calling the chain's ``fk`` on the eight
solutions instead would cost about 53 µs here, 2.9 yardsticks on its own.

Times are CPU seconds of this process divided by the yardstick of
``yardstick.py`` (a naive NumPy DH forward kinematics of the UR10), timed in the
same run, so that machine speed and load cancel in the ratio. The yardstick, the
single poses (blocks of 50) and the batch are timed in turns, each best-of-several,
for ``--rounds`` rounds; the best of each is kept (the comparable quiet moments of
a loaded machine).

Usage::

    python benchmarks/bench_ur_ik.py                 # 300 single poses, batches of 10,000
    python benchmarks/bench_ur_ik.py --n 100 --batch 1000 --solve-ik 0
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from yardstick import cpu_per_call, yardstick_seconds

from robokin.models import ur10, ur10_ik, ur10_ik_batch


def bench(n: int, batch: int, n_solve_ik: int, rounds: int = 3) -> None:
    chain = ur10()
    T = chain.fk(chain.random_configurations(n, seed=2024))
    TB = chain.fk(chain.random_configurations(batch, seed=2025)) if batch else None
    ur10_ik(T[0])  # warm-up
    # Rounds of yardstick, single poses (blocks of 50) and batch, each timed best-of-several: the
    # minima of all rounds are compared (on a loaded machine the quietest moments of each).
    yard, single, per_pose = np.inf, np.inf, np.inf
    blocks = [T[i: i + 50] for i in range(0, n, 50)]
    for _ in range(rounds):
        yard = min(yard, yardstick_seconds())
        single = min(single, sum(cpu_per_call(lambda block=block: [ur10_ik(pose) for pose in block], 1, repeat=5)
                                 for block in blocks) / n)
        if TB is not None:
            per_pose = min(per_pose, cpu_per_call(lambda: ur10_ik_batch(TB), 1, repeat=5) / batch)
    rows = [("ur10_ik (one pose, all solutions)", n, single, np.mean([len(ur10_ik(pose)) for pose in T]), 3.0)]
    if TB is not None:
        rows.append((f"ur10_ik_batch (N = {batch:,})", batch, per_pose,
                     float(ur10_ik_batch(TB).valid.sum(axis=1).mean()), 0.1))
    if n_solve_ik:
        from robokin.motion import solve_ik

        solve_ik(chain, T[0])
        cpu = np.empty(n_solve_ik)
        for i in range(n_solve_ik):
            c0 = time.process_time()
            solve_ik(chain, T[i], record_history=False)
            cpu[i] = time.process_time() - c0
        rows.append(("solve_ik default 'lm' (one solution; median)", n_solve_ik, float(np.median(cpu)), 1.0, None))
    print(f"UR10 closed-form IK; yardstick (naive DH FK) {1e6 * yard:.1f} µs CPU (best of {rounds} rounds)")
    print("| call | poses | CPU µs/pose | CPU / yardstick | goal | mean solutions |")
    print("|---|---|---|---|---|---|")
    for name, count, seconds, mean_solutions, goal in rows:
        goal_text = f"≤ {goal:g}" if goal is not None else "–"
        print(f"| {name} | {count:,} | {1e6 * seconds:.2f} | {seconds / yard:.3f} | {goal_text} "
              f"| {mean_solutions:.2f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=300, help="poses solved one at a time")
    ap.add_argument("--batch", type=int, default=10_000, help="poses of the batched call (0: skip)")
    ap.add_argument("--solve-ik", type=int, default=100, help="poses for the solve_ik row (0: skip)")
    ap.add_argument("--rounds", type=int, default=3, help="rounds of timings (the best of each is kept)")
    args = ap.parse_args()
    bench(args.n, args.batch, args.solve_ik, args.rounds)


if __name__ == "__main__":
    main()
