"""The IK solvers give the recorded results on 1,000 seeded cases: bit for bit on the recording
platform, to a stated tolerance on any other.

The cases (``tests/support/ik_identity_cases.py``) span the methods, five robots, pose
and position targets (reachable or not), masks, tools, wrapping, step caps,
restarts and the LM polish. ``tests/data/ik_identity_golden.npz`` holds, for every
case, the SHA-256 of the result's arrays (q, errors, every history array, the
scalars) and its outcome as values (q, success, reason).

- On the platform that recorded the file (same numpy, BLAS and CPU features), every
  digest must be equal: a refactoring of the solvers must not change a single bit.
- On any other platform the digests cannot be compared (other SIMD or BLAS kernels change
  last bits), so the outcomes are: each case that is not *sensitive* must keep its success
  and reason, and its q within ``Q_TOLERANCE`` (1e-6 rad or m, the solvers' default
  tolerance; last-bit changes move it by 2e-8 at most in 99 % of the solved cases), with at
  most ``VALUE_BUDGET`` (1 %) of them allowed to differ. Sensitive cases (under 2 % of them, whose
  outcome changed when the recording ran them again with other kernels) are left out of it.

A deliberate change of arithmetic regenerates the file (``python tests/support/ik_identity_cases.py``)
in its own commit that says so.
"""

from __future__ import annotations

import numpy as np
import pytest
from support.ik_identity_cases import (
    GOLDEN,
    Q_TOLERANCE,
    VALUE_BUDGET,
    batch_cases,
    digest_batch,
    digest_single,
    outcome_values,
    platform_fingerprint,
    robots,
    run_batch,
    run_single,
    single_cases,
    value_differences,
)


@pytest.fixture(scope="module")
def golden():
    with np.load(GOLDEN) as data:
        return {k: data[k] for k in data.files}


@pytest.fixture(scope="module")
def chains():
    return robots()


@pytest.fixture(scope="module")
def results(chains):
    """(single results, batch results) of every case, computed once for the module."""
    return ([run_single(case, chains) for case in single_cases()],
            [run_batch(case, chains) for case in batch_cases()])


@pytest.fixture(scope="module")
def same_platform(golden) -> bool:
    return str(golden["platform"]) == platform_fingerprint()


def _describe(case):
    return f"{case['robot']}/{case['label']}"


def test_single_target_results_are_unchanged_bit_for_bit(golden, results, same_platform):
    if not same_platform:
        pytest.skip(f"golden IK digests recorded on another platform ({golden['platform']}); "
                    "test_results_keep_their_recorded_values compares the values here")
    cases = single_cases()
    assert len(cases) >= 1000 and len(cases) == len(golden["single_digest"])
    changed = [f"#{i} {_describe(case)} (iterations {res.iterations}, recorded {golden['single_iterations'][i]})"
               for i, (case, res) in enumerate(zip(cases, results[0]))
               if digest_single(res) != golden["single_digest"][i].tobytes()]
    assert not changed, f"{len(changed)} of {len(cases)} results changed: " + "; ".join(changed[:10])


def test_batch_results_are_unchanged_bit_for_bit(golden, results, same_platform):
    if not same_platform:
        pytest.skip("golden IK digests recorded on another platform; test_results_keep_their_recorded_values "
                    "compares the values here")
    cases = batch_cases()
    assert len(cases) == len(golden["batch_digest"])
    changed = [f"#{i} {_describe(case)}" for i, (case, res) in enumerate(zip(cases, results[1]))
               if digest_batch(res) != golden["batch_digest"][i].tobytes()]
    assert not changed, f"{len(changed)} of {len(cases)} batch results changed: " + "; ".join(changed[:10])


@pytest.mark.parametrize("part", ["single", "batch"])
def test_results_keep_their_recorded_values(golden, results, part):
    """On every platform (on the recording one, the digests above say more)."""
    values = outcome_values(*results)
    assert values[f"{part}_q"].shape == golden[f"{part}_q"].shape
    compared = int((~golden[f"{part}_sensitive"]).sum())
    differ = value_differences(golden, values, part)
    q_difference = np.nanmax(np.abs(golden[f"{part}_q"] - values[f"{part}_q"]), axis=-1)
    detail = "; ".join(f"#{i}: success {golden[f'{part}_success'][i]} -> {values[f'{part}_success'][i]}, "
                       f"reason {golden[f'{part}_reason'][i]} -> {values[f'{part}_reason'][i]}, "
                       f"|dq| {q_difference[i]:.1e}" for i in differ[:10])
    assert len(differ) <= VALUE_BUDGET * compared, (
        f"{len(differ)} of {compared} {part} outcomes differ from the recorded ones (q beyond {Q_TOLERANCE} "
        f"or another success or reason; at most {VALUE_BUDGET:.0%} may): {detail}")


def test_the_cases_cover_every_outcome(golden):
    cases = single_cases()
    assert {c["label"] for c in cases} >= {"lm", "pinv", "transpose", "weighted", "dls", "nullspace"}
    assert {c["robot"] for c in cases} == set(robots())
    assert 0.3 < golden["single_success"].mean() < 0.9  # both successes and failures
    assert golden["single_sensitive"].mean() < 0.05  # the value comparison covers almost every case


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
