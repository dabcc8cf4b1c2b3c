"""Re-executing an unchanged notebook stores unchanged bytes: outputs, pictures and 3D scenes.

`make execute NB=...` is what an author runs after a change; if it rewrote the
pictures or scenes of a notebook nobody touched, every commit would carry noise and
a real change would hide in it. The tour holds matplotlib figures and MeshCat
scenes, "Your own robot" a scene with meshes: both are executed here exactly as
`make execute` does and compared byte for byte with the committed files.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT


@pytest.mark.parametrize("name", ["00_tour.ipynb", "00_your_robot.ipynb"])
def test_make_execute_of_an_unchanged_notebook_changes_no_byte(tmp_path, name):
    copy = tmp_path / name
    shutil.copyfile(ROOT / "notebooks" / name, copy)
    env = dict(os.environ, ROBOKIN_VIEWER="static")
    base = [sys.executable, "-m", "nbconvert", "--to", "notebook", "--inplace", "--log-level=WARN"]
    for extra in (["--execute", "--ExecutePreprocessor.timeout=300", "--ExecutePreprocessor.record_timing=False"],
                  ["--CoalesceStreamsPreprocessor.enabled=True"]):
        subprocess.run(base + extra + [str(copy)], cwd=ROOT / "notebooks", env=env, check=True,
                       capture_output=True)
    assert copy.read_bytes() == (ROOT / "notebooks" / name).read_bytes(), (
        f"make execute NB=notebooks/{name} changes the stored notebook although nothing changed")
