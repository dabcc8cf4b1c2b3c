"""Robustness property suite: every public entry point either works or says what is wrong.

For every public function of ``robokin.transforms``, ``chains``, ``models``,
``motion``, ``parallel`` and ``check`` (the table is in ``fuzz_specs``), hypothesis
draws arguments that are valid, valid but extreme (huge and tiny finite numbers,
empty batches) or corrupted (NaN, inf, wrong shapes, None, strings, lists of
strings, non-orthonormal and reflected rotations, ...). Each call must either
return finite values of the documented shape, or raise a robokin error /
``ValueError`` / ``TypeError`` whose message names the offending argument (an
exercise check given a broken *student answer* returns a failed ``CheckResult``
instead). ``fuzz_support.run_example`` is the oracle.

Budget: the default hypothesis profile runs 100 examples per function times its spec's
``weight`` (at least 3; about 15,000 over the 238 specs, 63 per spec on average),
derandomised so that CI is reproducible: about 40 CPU-s on the 2-core machine;
``pytest tests/test_robustness_fuzz.py --hypothesis-profile=long`` runs ten
times as many with fresh random examples.
"""

from __future__ import annotations

import inspect
import math

import pytest
from support.fuzz_specs import all_specs
from support.fuzz_support import Outcome, run_example
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robokin.chains
import robokin.check
import robokin.models
import robokin.motion
import robokin.parallel
import robokin.transforms
from robokin.check._registry import CHAPTERS, checks_of

SPECS = all_specs()
#: Examples per function: the active profile's max_examples (100 by default) times this share.
SHARE = 1.0
SCALE = settings().max_examples / 100.0


def _settings(spec) -> settings:
    n = max(3, math.ceil(settings().max_examples * SHARE * spec.weight))
    return settings(max_examples=n, deadline=None, database=None, derandomize=SCALE <= 1.0,
                    suppress_health_check=list(HealthCheck), print_blob=True)


@pytest.mark.parametrize("spec", SPECS, ids=[s.name for s in SPECS])
def test_public_function_rejects_or_handles_bad_input(spec):
    @_settings(spec)
    @given(data=st.data())
    def run(data):
        run_example(spec, data)

    run()


# ---------------------------------------------------------------------- coverage
#: Public names that are not functions taking input (constants, result containers, base classes).
NOT_ENTRY_POINTS = {
    # results / containers: built by robokin, only read by users
    "motion.IKResult", "motion.IKHistory", "motion.IKBatchResult", "motion.ControlOutput",
    "motion.SimulationLog", "motion.BatchTrackingLog", "motion.Trajectory", "models.AR601IKResult",
    "models.URIKResult", "models.URIKBatchResult", "motion.PoseTrajectory",
    "parallel.ForwardKinematicsResult", "models.RobotInfo", "check.CheckResult", "check.Diagnosis", "check.Mistake",
    "check.Variable", "check.Check", "chains.Element",
    # abstract base class of the IK step rules; typing protocols of a chain (never called)
    "motion.IKMethod", "chains.Chain", "chains.DrawableChain",
    # registries and constants
    "motion.METHODS", "motion.REASONS", "check.CHAPTERS",
    # diagnosis builders for check authors (take reference functions, not user input)
    "check.mistake", "check.alternatives",
}


def public_entry_points() -> set[str]:
    """Qualified names of the public callables of the covered packages."""
    names: set[str] = set()
    for short, mod in (("transforms", robokin.transforms), ("chains", robokin.chains),
                       ("models", robokin.models), ("motion", robokin.motion),
                       ("parallel", robokin.parallel), ("check", robokin.check)):
        for name in mod.__all__:
            obj = getattr(mod, name)
            if not callable(obj):
                continue
            names.add(f"{short}.{name}")
    for cls, short in ((robokin.chains.SerialChain, "SerialChain"), (robokin.parallel.Planar3RPR, "Planar3RPR"),
                       (robokin.motion.CartesianController, "CartesianController")):
        names.add(short)
        for name, member in inspect.getmembers(cls):
            if (name.startswith("_") and name != "__call__") or isinstance(inspect.getattr_static(cls, name),
                                                                           (property, classmethod)):
                continue
            if callable(member):
                names.add(f"{short}.{name}")
    for chapter in CHAPTERS:
        for attr in checks_of(chapter):
            names.add(f"check.{chapter}.{attr}")
    return names


def _spec_covers() -> set[str]:
    out: set[str] = set()
    for s in SPECS:
        out |= set(s.covers) if s.covers else {s.name}
    return out


#: Spec names that cover a public name under another spelling.
ALIASES = {
    "SerialChain": "chains.SerialChain", "Planar3RPR": "parallel.Planar3RPR",
    "CartesianController": "motion.CartesianController",
}


def test_every_public_entry_point_has_a_spec():
    covered = _spec_covers()
    covered |= {ALIASES[c] for c in covered if c in ALIASES}
    missing = sorted(n for n in public_entry_points() - NOT_ENTRY_POINTS
                     if n not in covered and f"models.{n.split('.', 1)[1]}" not in covered)
    # methods inherited from classmethod builders are covered by chains.from_*
    missing = [m for m in missing if m not in {"SerialChain.from_dh", "SerialChain.from_modified_dh",
                                               "SerialChain.from_link_table"}]
    assert not missing, (f"public entry points without a robustness spec: {missing}. Add a Spec for each to "
                         f"tests/support/fuzz_specs.py (how to call it with valid input; the suite corrupts each "
                         f"argument), or list a result container in NOT_ENTRY_POINTS in "
                         f"tests/test_robustness_fuzz.py")


def test_zz_report(capsys):
    """Print how many functions and examples the suite covered (for the record)."""
    functions = len(public_entry_points() - NOT_ENTRY_POINTS)
    line = (f"\nrobustness fuzz: {len(SPECS)} specs covering {functions} public functions and methods, "
            f"{Outcome.examples} examples run in this session")
    with capsys.disabled():
        print(line)
    assert Outcome.examples >= 0
