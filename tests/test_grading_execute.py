"""The settings of autograde's executor, ``BridgedExecute`` (tools/grading/bridge/execute.py).

An older ``nbgrader_config.py`` is not ignored silently: a setting under the executor's
former name (``c.RobokinExecute.sandbox``, ``c.RobokinExecute.viewer``) still applies,
with a warning naming the new one, unless the new name sets it too; a retired setting
(``c.BridgedExecute.chapters``) is ignored with a warning saying why. These tests build
the executor from a configuration only: no kernel starts, each takes milliseconds. The
grading itself is tested by ``tests/test_nbgrader.py`` and the trust and tamper suites.
"""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from traitlets.config import Config, Configurable
from traitlets.config.loader import KVArgParseConfigLoader, PyFileConfigLoader

from support import installed

installed.require("nbgrader", "nbgrader is not installed: run `make test` (installs requirements.txt)")

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def bridge_execute():
    """``tools.grading.bridge.execute``, imported when a test runs: it imports nbgrader (1.3 CPU-s),
    which collecting this module, in every pytest worker of a run, need not."""
    from tools.grading.bridge import execute

    return execute


def _warnings(caplog) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]


@pytest.mark.parametrize("value", [["*"], ["01_leg_kinematics"], []])
def test_an_old_chapters_setting_is_a_warning_naming_it(value, caplog, bridge_execute):
    """``c.BridgedExecute.chapters`` of an older nbgrader_config.py: every chapter is graded through
    the bridge now; the instructor is told the setting is ignored and may go, not a grading error."""
    with caplog.at_level(logging.WARNING):
        execute = bridge_execute.BridgedExecute(config=Config({"BridgedExecute": {"chapters": value}}))
    assert not hasattr(execute, "chapters")
    warnings = _warnings(caplog)
    assert any(w.startswith("c.BridgedExecute.chapters is no longer needed and is ignored: every chapter is "
                            "graded through the bridge") and "Remove it from nbgrader_config.py" in w
               for w in warnings), warnings


@pytest.mark.parametrize("how", ["config", "parent", "command line"])
@pytest.mark.parametrize(("name", "value", "default"), [("sandbox", False, True), ("viewer", "plotly", "matplotlib")])
def test_a_setting_under_the_former_name_still_applies_and_names_the_new_one(how, name, value, default, caplog,
                                                                             bridge_execute):
    """``c.RobokinExecute.sandbox = False`` of an older configuration (nbgrader_config.py, given to the
    executor or to the exporter that makes it, or ``--RobokinExecute.sandbox=False`` on nbgrader's
    command line, whose value is a string until a trait reads it) still turns the sandbox off."""
    if how == "command line":
        config = KVArgParseConfigLoader(argv=[f"--RobokinExecute.{name}={value}"]).load_config()
    else:
        config = Config({"RobokinExecute": {name: value}})
    with caplog.at_level(logging.WARNING):
        execute = (bridge_execute.BridgedExecute(parent=Configurable(config=config)) if how == "parent"
                   else bridge_execute.BridgedExecute(config=config))
    assert getattr(execute, name) == value != default
    assert _warnings(caplog) == [f"c.RobokinExecute.{name} is now c.BridgedExecute.{name} (the executor's one name); "
                                 "it still applies. Rename it in nbgrader_config.py (book/for-instructors.md, "
                                 "\"Where the verdicts are decided\")."]


def test_the_new_name_wins_over_the_former_one_and_says_so(caplog, bridge_execute):
    config = Config({"RobokinExecute": {"sandbox": True, "viewer": "plotly"},
                     "BridgedExecute": {"sandbox": False}})
    with caplog.at_level(logging.WARNING):
        execute = bridge_execute.BridgedExecute(config=config)
    assert execute.sandbox is False and execute.viewer == "plotly"
    warnings = _warnings(caplog)
    assert any(w.startswith("c.RobokinExecute.sandbox is ignored: c.BridgedExecute.sandbox, also set, is the one "
                            "that applies.") for w in warnings), warnings
    assert any(w.startswith("c.RobokinExecute.viewer is now c.BridgedExecute.viewer") for w in warnings), warnings


@pytest.mark.parametrize(("name", "value"), [("no_such_setting", 1), ("chapters", ["*"])])
def test_an_unknown_or_retired_setting_under_the_former_name_is_a_warning(name, value, caplog, bridge_execute):
    with caplog.at_level(logging.WARNING):
        execute = bridge_execute.BridgedExecute(config=Config({"RobokinExecute": {name: value}}))
    assert not hasattr(execute, name)
    expected = ("no longer needed and is ignored" if name in bridge_execute.RETIRED_SETTINGS
                else "is no setting of the executor and is ignored")
    assert any(w.startswith(f"c.RobokinExecute.{name} ") and expected in w for w in _warnings(caplog)), caplog.text


def test_the_executor_has_one_name(bridge_execute):
    """The former class is gone: its name lives on only as a configuration section that is read."""
    import tools.grading.robokin_nbgrader as robokin_nbgrader

    assert bridge_execute.FORMER_NAMES == ("RobokinExecute",)
    assert not any(hasattr(robokin_nbgrader, former) for former in bridge_execute.FORMER_NAMES)
    assert bridge_execute.BridgedExecute.__name__ not in bridge_execute.FORMER_NAMES


def test_the_course_configuration_gives_no_warning_and_keeps_the_sandbox(caplog, bridge_execute):
    """The repository's nbgrader_config.py, as nbgrader loads it: the sandbox on, 3D scenes as
    pictures, the fork server on, and no setting warned about."""
    config = PyFileConfigLoader("nbgrader_config.py", path=str(ROOT)).load_config()
    assert not any(former in config for former in bridge_execute.FORMER_NAMES)
    with caplog.at_level(logging.WARNING):
        execute = bridge_execute.BridgedExecute(config=config)
    assert (execute.sandbox, execute.viewer, execute.fork_server, execute.call_timeout) == (
        True, "matplotlib", True, 30.0)
    assert not _warnings(caplog)


def test_a_current_configuration_gives_no_such_warning(caplog, bridge_execute):
    with caplog.at_level(logging.WARNING):
        bridge_execute.BridgedExecute(fork_server=False, sandbox=False)
    assert not _warnings(caplog)


def _cells(*specs: tuple[str, str, bool]) -> list[dict]:
    return [{"grade_id": grade_id, "source": source, "test": test} for grade_id, source, test in specs]


PICTURE = ["nbval-ignore-output"]


def test_a_picture_that_defines_nothing_a_running_cell_reads_is_skipped(bridge_execute):
    cells = _cells(
        ("data", "x = 1.0", False),
        ("helper-picture", "def draw(a):\n    return a\nfigure = draw(x)", False),
        ("picture", "draw(x + 1)", False),   # reads draw, but is skipped itself
        ("test", "assert x == 1.0", True),
        ("after", "print(figure)", False),   # after the last test: not run, reads nothing
    )
    bridge_execute.skip_pictures(cells, {"helper-picture": PICTURE, "picture": PICTURE})
    assert [item.get("skip", False) for item in cells] == [False, True, True, False, True]


def test_a_picture_whose_name_a_test_or_a_running_cell_reads_is_run(bridge_execute):
    cells = _cells(
        ("picture", "y = 2.0", False),
        ("given", "z = y + 1", False),
        ("picture-2", "w = 3.0", False),
        ("test", "assert w == 3.0 and z == 3.0", True),
    )
    bridge_execute.skip_pictures(cells, {"picture": PICTURE, "picture-2": PICTURE})
    assert [item.get("skip", False) for item in cells] == [False, False, False, False]
