"""The IK solvers give bit-for-bit the recorded results on 1,000 seeded cases.

The cases (``tests/ik_identity_cases.py``) span the methods, five robots, pose
and position targets (reachable or not), masks, tools, wrapping, step caps,
restarts and the LM polish; ``tests/data/ik_identity_golden.npz`` holds the
SHA-256 of every result's arrays (q, errors, every history array, the
scalars) as computed before the solver loop was restructured.  A refactoring
of the loop must not change a single bit; a deliberate change of arithmetic
regenerates the file (``python tests/ik_identity_cases.py``) in its own commit.

Bit-for-bit equality holds on the same arithmetic only: on a platform other than
the recorded one (numpy, BLAS, CPU features) the comparisons are skipped.
"""

from __future__ import annotations

import numpy as np
import pytest
from ik_identity_cases import (
    GOLDEN,
    batch_cases,
    digest_batch,
    digest_single,
    platform_fingerprint,
    robots,
    run_batch,
    run_single,
    single_cases,
)


@pytest.fixture(scope="module")
def golden():
    with np.load(GOLDEN) as data:
        recorded = {k: data[k] for k in data.files}
    if str(recorded["platform"]) != platform_fingerprint():
        pytest.skip(f"golden IK digests recorded on another platform ({recorded['platform']}); "
                    "regenerate them here with python tests/ik_identity_cases.py to compare")
    return recorded


@pytest.fixture(scope="module")
def chains():
    return robots()


def _describe(case):
    return f"{case['robot']}/{case['label']}"


def test_single_target_results_are_unchanged(golden, chains):
    cases = single_cases()
    assert len(cases) >= 1000 and len(cases) == len(golden["single_digest"])
    changed = []
    for i, case in enumerate(cases):
        res = run_single(case, chains)
        if digest_single(res) != golden["single_digest"][i].tobytes():
            changed.append(f"#{i} {_describe(case)} (iterations {res.iterations}, "
                           f"recorded {golden['single_iterations'][i]})")
    assert not changed, f"{len(changed)} of {len(cases)} results changed: " + "; ".join(changed[:10])


def test_batch_results_are_unchanged(golden, chains):
    cases = batch_cases()
    assert len(cases) == len(golden["batch_digest"])
    changed = [f"#{i} {_describe(case)}" for i, case in enumerate(cases)
               if digest_batch(run_batch(case, chains)) != golden["batch_digest"][i].tobytes()]
    assert not changed, f"{len(changed)} of {len(cases)} batch results changed: " + "; ".join(changed[:10])


def test_the_cases_cover_every_outcome(golden):
    cases = single_cases()
    assert {c["label"] for c in cases} >= {"lm", "pinv", "transpose", "weighted", "dls", "nullspace"}
    assert {c["robot"] for c in cases} == set(robots())
    assert 0.3 < golden["single_success"].mean() < 0.9  # both successes and failures


def test_solve_ik_once_is_solve_ik_without_restarts_and_polish(chains):
    """One attempt of the method alone equals solve_ik(..., restarts=0, polish=False) bit for bit."""
    from robokin.motion import solve_ik, solve_ik_once

    cases = [c for c in single_cases()[:300] if c.get("seed") is None][:120]
    for case in cases:
        kwargs = {k: v for k, v in case.items() if k not in ("robot", "label", "restarts", "polish")}
        chain = chains[case["robot"]]
        once = solve_ik_once(chain, **kwargs)
        full = solve_ik(chain, **kwargs, restarts=0, polish=False)
        assert once.attempts == 1
        assert digest_single(once) == digest_single(full), _describe(case)
