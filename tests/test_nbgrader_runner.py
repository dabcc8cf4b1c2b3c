"""nbgrader commands forked from a warm process (tests/support/nbgrader_runner.py) behave as new processes.

The grading suites run their nbgrader commands through the runner; the
walk-through of tests/test_nbgrader.py runs the console script itself. Here: the
same output and exit code as the console script, the request's folder and
environment (a course's ``nbgrader_config.py`` is Python, so it can print them),
a command past its time limit killed without harming the next one, a runner slow to start
taking none of a command's time limit, commands that end at once following each other, and
no process left when the runners are closed. The suite's shortcuts that the runner applies: in
every command, each with the result of nbgrader's or nbconvert's own code.
"""

from __future__ import annotations

import os
import subprocess
import textwrap

import pytest

from conftest import ROOT
from support import installed

installed.require("nbgrader", "nbgrader is not installed: run `make test` (installs requirements.txt)")
psutil = pytest.importorskip("psutil")

from support import nbgrader_runner  # noqa: E402
from tools.authoring import student_edition  # noqa: E402

pytestmark = pytest.mark.nbgrader

#: A course configuration that tells where and with what it runs (nbgrader executes it).
PROBE_CONFIG = textwrap.dedent("""\
    import os, sys
    import nbconvert.exporters.html, nbgrader.api, nbgrader.nbgraderformat.common
    print("PROBE", os.getcwd(), os.environ.get("ROBOKIN_PROBE"), sys.argv[1:], flush=True)
    print("SHORTCUTS", nbgrader.api.get_alembic_version.__name__,
          type(nbgrader.nbgraderformat.common.jsonschema).__name__,
          nbconvert.exporters.html.Highlight2HTML.__name__,
          nbconvert.exporters.html.HTMLExporter.markdown2html.__name__, flush=True)
    if os.environ.get("ROBOKIN_PROBE") == "sleep":
        import time
        time.sleep(60)
""")


#: Seconds a command that ends by itself may take: ``nbgrader --version`` or ``db student list`` take
#: well under a second from a runner (a fork of a process that imported nbgrader) and about 2 s as a
#: new process on the quiet 2-core machine; 120 s is a ceiling no load reaches without a hang.
ENDS = 120
#: Seconds before a command that never ends (the probe's 60 s sleep) is killed: the probe prints
#: within a second of the start at a load of 16; the limit expires in the sleep, 50 s before it ends.
NEVER_ENDS = 10


def environment(**extra: str) -> dict[str, str]:
    return {**student_edition.environment(), **extra}


@pytest.mark.parametrize("args", [["--version"], ["autograde", "no_such_assignment"]])
def test_output_and_exit_code_are_the_console_scripts(tmp_path, args):
    new = subprocess.run([*student_edition.nbgrader_command(), *args], cwd=tmp_path, env=environment(),
                         capture_output=True, text=True, timeout=ENDS)
    forked = nbgrader_runner.run(args, tmp_path, environment(), timeout=ENDS)
    assert forked.returncode == new.returncode
    assert forked.stdout == new.stdout + new.stderr   # stdout and stderr go to one file, in order


def test_a_command_runs_in_its_folder_with_its_environment(tmp_path):
    runs = []
    for name in ("first", "second"):
        course = tmp_path / name
        course.mkdir()
        (course / "nbgrader_config.py").write_text(PROBE_CONFIG)
        runs.append(nbgrader_runner.run(["db", "student", "list"], course, environment(ROBOKIN_PROBE=name),
                                        timeout=ENDS))
    for name, run in zip(("first", "second"), runs):
        assert run.returncode == 0, run.stdout
        assert f"PROBE {tmp_path / name} {name} ['db', 'student', 'list']" in run.stdout
        # the suite's shortcuts, applied by the runner before it forked the command
        assert "SHORTCUTS alembic_head SchemaCheckedOnce MemoisedHighlight memoised" in run.stdout


def test_a_command_past_its_time_limit_is_killed_and_the_next_one_runs(tmp_path):
    (tmp_path / "nbgrader_config.py").write_text(PROBE_CONFIG)
    with pytest.raises(subprocess.TimeoutExpired) as caught:
        nbgrader_runner.run(["db", "student", "list"], tmp_path, environment(ROBOKIN_PROBE="sleep"), timeout=NEVER_ENDS)
    assert "PROBE" in caught.value.output
    after = nbgrader_runner.run(["--version"], tmp_path, environment(), timeout=ENDS)
    assert after.returncode == 0 and "nbgrader version" in after.stdout


def test_a_runner_slow_to_start_takes_none_of_the_commands_time_limit(tmp_path):
    """A command's time limit counts from its start: a runner that is still importing nbgrader
    (seconds on a busy machine; here it sleeps past the limit first) does not use it up."""
    slow = tmp_path / "slow"
    slow.mkdir()
    (slow / "sitecustomize.py").write_text(f"import time\ntime.sleep({NEVER_ENDS + 2})\n")
    env = environment()
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(slow), env.get("PYTHONPATH")]))
    run = nbgrader_runner.run(["--version"], tmp_path, env, timeout=NEVER_ENDS)
    assert run.returncode == 0 and "nbgrader version" in run.stdout


def test_commands_that_end_at_once_follow_each_other_without_waiting(tmp_path):
    """A command's two replies (started, ended) can arrive together: neither may be waited for again."""
    for _ in range(20):
        run = nbgrader_runner.run(["--version"], tmp_path, environment(), timeout=ENDS)
        assert run.returncode == 0 and "nbgrader version" in run.stdout


def test_closed_runners_leave_no_process():
    nbgrader_runner.run(["--version"], ROOT, environment(), timeout=ENDS)
    runners = nbgrader_runner.runner_pids()
    assert runners and all(psutil.Process(pid).num_threads() == 1 for pid in runners)   # forks safely
    nbgrader_runner.close_all()
    assert not nbgrader_runner.runner_pids()
    assert not [pid for pid in runners if psutil.pid_exists(pid)]


def test_alembic_head_is_the_revision_nbgrader_reads(monkeypatch):
    """The shortcut reads the revision that nbgrader's ``alembic heads`` (a program of its own) prints."""
    from nbgrader import api

    monkeypatch.setenv("PATH", environment()["PATH"])   # nbgrader runs alembic from PATH
    assert nbgrader_runner.alembic_head() == api.get_alembic_version()


@pytest.mark.parametrize("metadata", [
    {"grade": True, "grade_id": "task1_test1", "locked": True, "points": 2, "schema_version": 3, "solution": False},
    {"grade": False, "grade_id": "task1_answer", "locked": False, "schema_version": 3, "solution": True},
    {"grade": "yes", "grade_id": "task1_test1", "locked": True, "points": 2, "schema_version": 3, "solution": False},
    {"grade": True, "locked": True, "points": 2, "schema_version": 3, "solution": False},
    {"grade": True, "grade_id": 7, "locked": True, "points": "two", "schema_version": 3, "solution": False},
])
def test_the_schema_checked_once_gives_jsonschemas_verdicts(metadata):
    """nbgrader's metadata check through the shortcut: the verdict ``jsonschema.validate`` gives
    (none, or the same best-matching error), on a second call too (the validator kept)."""
    import jsonschema
    from nbgrader.nbgraderformat import MetadataValidator

    schema = MetadataValidator().schema
    try:
        jsonschema.validate(metadata, schema)
        expected = None
    except jsonschema.ValidationError as error:
        expected = (error.message, list(error.path))
    checked_once = nbgrader_runner.SchemaCheckedOnce()
    for _ in range(2):
        try:
            checked_once.validate(metadata, schema)
            got = None
        except jsonschema.ValidationError as error:
            got = (error.message, list(error.path))
        assert got == expected
    assert checked_once.ValidationError is jsonschema.ValidationError   # the rest is jsonschema's


def test_memoised_highlighting_and_markdown_change_no_page(monkeypatch):
    """nbconvert's HTML page, byte for byte, with the memoised filters (twice: the second page is
    made from the memo), for markdown with a formula and HTML, code, its outputs and a cell magic."""
    import copy

    import nbconvert.exporters.html as nbconvert_html
    import nbformat

    nb = nbformat.v4.new_notebook(metadata={"language_info": {"name": "python", "pygments_lexer": "ipython3"}})
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: a formula $T_{BA} = T_{AB}^{-1}$ and `code` <b>bold</b> &amp;"),
        nbformat.v4.new_code_cell("import numpy as np\n\ndef f(q):\n    return np.sin(q) @ q  # a comment\n",
                                  outputs=[nbformat.v4.new_output("stream", name="stdout", text="<x> & 'y'\n"),
                                           nbformat.v4.new_output("error", ename="ValueError", evalue="bad",
                                                                  traceback=["\x1b[31mValueError\x1b[0m: bad"])]),
        nbformat.v4.new_code_cell("%%bash\necho hi", metadata={"magics_language": "bash"}),
    ]
    plain = nbconvert_html.HTMLExporter().from_notebook_node(copy.deepcopy(nb))[0]
    monkeypatch.setattr(nbconvert_html, "Highlight2HTML", nbgrader_runner.memoised_highlight())
    monkeypatch.setattr(nbconvert_html.HTMLExporter, "markdown2html",
                        nbgrader_runner.memoised_markdown(nbconvert_html.HTMLExporter.markdown2html))
    for _ in range(2):
        assert nbconvert_html.HTMLExporter().from_notebook_node(copy.deepcopy(nb))[0] == plain
