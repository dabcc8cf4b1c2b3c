"""The test suite's harness: what the test modules share, and no test of its own.

pytest puts ``tests/`` on ``sys.path`` (its default "prepend" import mode: ``tests/`` has no
``__init__.py``), so a test module imports these as ``from support import tiers`` or
``from support.grading_course import reads``.

=====================  ===========================================================================
module                 what it holds
=====================  ===========================================================================
``tiers``              which check is in which tier (``make test`` or ``make test-all`` only)
``parallel_plan``      how a run uses both cores: xdist workers, groups, longest parts first
``cpu_accounting``     each test's CPU-seconds, its children's included (``ROBOKIN_CPU_REPORT``)
``nbgrader_course``    a chapter's nbgrader course, its submissions, its autograde run, the gradebook
``grading_course``     the autograde runs the grading suites share (one per chapter)
``nbgrader_runner``    nbgrader's command lines in processes forked from one that imported nbgrader
``installed``         skipping a module whose requirement is missing, without importing it (nbgrader)
``forked_kernels``     nbval's kernels forked from a warm fork server (the root ``conftest.py``)
``tampering``         submissions that tamper with the grading, by kind (they must gain nothing)
``benign_variants``    correct answers written another way, per chapter (full marks expected)
``browser_waits``      waiting for a page in headless Chromium by a condition, not a fixed sleep
``finite_differences`` central differences of a chain's pose, the reference of the Jacobian tests
``fuzz_specs``         the public functions the robustness suite corrupts the input of
``fuzz_support``       that suite's argument generators and its oracle
``ik_support``         robots and reachable targets for the motion tests
``ik_identity_cases``  the seeded IK cases recorded bit for bit (``data/ik_identity_golden.npz``)
``numerical_noise``    NumPy's linear algebra made to round the way another computer's would
``views_doubles``      tiny chains that follow the chain contract, for the view tests
=====================  ===========================================================================
"""
