"""pytest's configuration for the whole repository (``tests/conftest.py`` has the tests' own).

The kernels nbval starts for ``notebooks/`` talk over sockets in a private folder,
not TCP ports: ``tools/kernel_sockets.py`` says why (two kernels started at the same
moment by different processes can be handed the same port, and one dies before its
first cell; ``make test`` runs two workers and, for other machines, three nbval runs
at once). nbval builds its kernel manager from the name ``KernelManager`` in
``nbval.kernel``; that name is pointed at jupyter_client's manager with private
sockets, and nothing else of nbval changes. The manager is
``tests/support/forked_kernels.py``'s: each kernel is forked from a process that
imported ipykernel and the notebooks' modules once (one per pytest process and
environment, stopped at the end of the session); one that cannot be forked starts
as a new process, with a warning.

Every process of a run computes with one OpenBLAS thread (``OPENBLAS_NUM_THREADS=1``, unless
the environment sets it): a run has a dozen processes on two cores (pytest's workers, the
notebooks', students' and grader kernels, ...), and OpenBLAS's default, a thread per core in
each, cost the in-process tests 9 % more CPU (164 against 150 CPU-s, ``make quick``'s tests on
the 2-core machine, the two settings one after the other). The stored outputs hold either way:
the other machines run the notebooks with one and two threads, and the perturbed one with
OpenBLAS's default (tests/test_notebooks_other_machines.py).
"""

from __future__ import annotations

import os

import nbval.kernel
import pytest

from tests.support import forked_kernels

nbval.kernel.KernelManager = forked_kernels.ForkedNbvalKernelManager

#: set before pytest-xdist starts its workers, which start the kernels: every process inherits it
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


@pytest.hookimpl(tryfirst=True)
def pytest_sessionfinish(session, exitstatus):
    """Stop this process's fork server of nbval kernels (each xdist worker has its own), before
    tests/conftest.py looks for processes the tests left running (its ``pytest_sessionfinish``)."""
    forked_kernels.stop_server()
