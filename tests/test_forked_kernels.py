"""nbval's kernel manager (tests/support/forked_kernels.py): a kernel that is not forked says so.

Cheap checks, no kernel started: what the manager would launch. That the forked kernels
pass every notebook unchanged is nbval's own run (``pytest notebooks/``), and that a forked
kernel computes with its run's BLAS settings is ``tests/test_notebooks_other_machines.py``.
"""

from __future__ import annotations

import pytest

from support import forked_kernels


def _no_fork_server(preload):
    raise forked_kernels.fork_server.ForkServerError("no fork here")


@pytest.fixture
def no_server(monkeypatch):
    """As if the fork server could not start in this process."""
    monkeypatch.setattr(forked_kernels, "_STATE", {})
    monkeypatch.setattr(forked_kernels.fork_server, "ForkServer", _no_fork_server)


def test_a_kernel_without_server_starts_as_a_new_process_with_a_warning(no_server):
    manager = forked_kernels.ForkedNbvalKernelManager(kernel_name="python3")
    try:
        with pytest.warns(forked_kernels.KernelNotForked, match="no fork here"):
            command, _ = manager.pre_start_kernel()
        assert "fork_launcher.py" not in " ".join(command)
        assert command[1:3] == ["-c", forked_kernels.fork_server.UNLIMITED_IOPUB_KERNEL]
    finally:
        manager.cleanup_resources()


def test_the_launchers_fallback_line_is_reported(tmp_path):
    stderr = tmp_path / forked_kernels.STDERR_FILE
    stderr.write_text("noise\n" + forked_kernels.LAUNCHER_FALLBACK + " this grader kernel (refused)\n")
    with pytest.warns(forked_kernels.KernelNotForked, match="refused"):
        forked_kernels._report_fallback(stderr)


def test_a_kernels_stderr_without_the_line_is_no_fallback(tmp_path, recwarn):
    stderr = tmp_path / forked_kernels.STDERR_FILE
    stderr.write_text("a C library's message\n")
    forked_kernels._report_fallback(stderr)
    forked_kernels._report_fallback(tmp_path / "missing.log")
    assert not [w for w in recwarn if issubclass(w.category, forked_kernels.KernelNotForked)]
