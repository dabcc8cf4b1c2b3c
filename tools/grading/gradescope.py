#!/usr/bin/env python3
"""Write a Gradescope autograder for one chapter (``make gradescope``).

    make gradescope CH=03_three_rpr                 # -> _build/gradescope/03_three_rpr.zip
    make gradescope CH=03_three_rpr MAX_PROCESSES=256   # the cap on processes made in the container
    .venv/bin/python tools/grading/gradescope.py 03_three_rpr --out autograder.zip --memory 4096 --max-processes 0

The zip is what Gradescope's "Configure Autograder" page takes (a zip archive with
``setup.sh`` and ``run_autograder`` at its top, unpacked into ``/autograder/source``):

``setup.sh``
    Run once, as root, when Gradescope builds the autograder's image (Ubuntu with
    ``python3``): installs bubblewrap (the sandbox of every submission's kernel), a
    Python of at least 3.11 when the image's is older, and the pinned requirements
    (``requirements.txt`` with ``constraints.txt``) into the virtual environment
    ``$AUTOGRADER_ROOT/venv``; then assigns the chapter once, in a template course
    ``$AUTOGRADER_ROOT/template/course`` (``grade_submission.py --assign``).
``run_autograder``
    Run for each submission: grades the one notebook in ``$AUTOGRADER_ROOT/submission/``
    with ``tools/grading/grade_submission.py`` (the course's own pipeline: sandbox, grader kernel,
    restarts, diagnoses, points, memory and CPU caps), in a copy of the template course where
    ``setup.sh`` made it (``--template``; without it the chapter is assigned for the
    submission, about 0.7 CPU-seconds more), and writes
    ``$AUTOGRADER_ROOT/results/results.json`` (Gradescope's format) and ``feedback.html``.
    Its ``--max-processes`` is this tool's (default :data:`GRADESCOPE_MAX_PROCESSES`, 0: no cap
    on the kernel's processes, Gradescope's container being the cap; see there why).
    ``AUTOGRADER_ROOT`` defaults to ``/autograder``: set it to run the autograder anywhere
    (tests/test_grading_engines.py does, in a temporary folder).

and the repository files that grading needs: ``robokin/``, ``tools/grading/`` with the shared
modules of ``tools/`` (not the authoring scripts), the chapter's
notebook (the instructor's source: its solutions and hidden tests, from which the student
edition is made and graded), ``nbgrader_config.py``, ``book/references.bib`` (the feedback's
citations), ``pyproject.toml``, ``README.md``, ``requirements.txt`` and ``constraints.txt``.
No other chapter is in it. The zip is the instructor's and holds a solution: upload it to
Gradescope, never give it to students.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import zipfile
from pathlib import Path

from tools.grading.grade_submission import DEFAULT_CPU_SECONDS, DEFAULT_MEMORY_MIB, add_cap_options
from tools.grading.process_cap import DEFAULT_MAX_PROCESSES

ROOT = Path(__file__).resolve().parents[2]

#: Folders whose files tracked by git go into the zip (not their caches or untracked files): the
#: package, and of ``tools/`` the grading runtime (the authoring scripts stay out).
FOLDERS = ("robokin", "tools/grading")
#: Single files of the repository that grading (or installing robokin) needs: the shared modules of
#: ``tools/`` beside the grading runtime.
FILES = ("nbgrader_config.py", "pyproject.toml", "README.md", "requirements.txt", "constraints.txt",
         "book/references.bib", "tools/__init__.py", "tools/notebook_analysis.py", "tools/kernel_sockets.py")

#: ``grade_submission.py --max-processes`` in ``run_autograder``: 0, no cap on the processes of the
#: submission's kernel. Gradescope grades each submission as root in a container of its own; as root
#: the cap needs a writable ``pids`` cgroup (tools/grading/process_cap.py), which a container's read-only
#: ``/sys/fs/cgroup`` does not give, and grading would stop on every submission. The container, thrown
#: away after the submission and under Gradescope's own limits, is then the cap (grade_submission.py
#: logs the missing cap on every submission). Where the container does give a writable ``pids``
#: cgroup, pass :data:`process_cap.DEFAULT_MAX_PROCESSES` (``make gradescope MAX_PROCESSES=256``).
GRADESCOPE_MAX_PROCESSES = 0

SETUP = r'''#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder's image (Ubuntu with python3).
# Written by robokin's tools/grading/gradescope.py.
set -euo pipefail
ROOT="${AUTOGRADER_ROOT:-/autograder}"
cd "$ROOT/source"
export DEBIAN_FRONTEND=noninteractive
apt-get update
# bubblewrap: every submission's kernel runs in its sandbox (tools/grading/sandbox.py)
apt-get install -y --no-install-recommends bubblewrap python3-venv
PYTHON=python3
if ! python3 -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else 1)'; then
  # robokin needs Python >= 3.11; Ubuntu 22.04's python3 is 3.10, its python3.11 package is newer
  apt-get install -y --no-install-recommends python3.11 python3.11-venv
  PYTHON=python3.11
fi
"$PYTHON" -m venv "$ROOT/venv"
"$ROOT/venv/bin/python" -m pip install --upgrade pip
# the pinned requirements (constraints.txt pins every transitive package); robokin itself from here
"$ROOT/venv/bin/python" -m pip install -r requirements.txt
# the chapter (the zip's one notebook) assigned once, in a template course that run_autograder copies
# for each submission instead of assigning the chapter again (about 0.7 CPU-seconds less per submission)
CHAPTER="$(basename notebooks/*.ipynb .ipynb)"
"$ROOT/venv/bin/python" -m tools.grading.grade_submission "$CHAPTER" --assign "$ROOT/template"
'''

RUN = r'''#!/usr/bin/env bash
# Gradescope runs this for each submission. Written by robokin's tools/grading/gradescope.py for {chapter}.
# AUTOGRADER_ROOT (default /autograder) holds source/ (this zip), submission/ and results/.
set -uo pipefail
CHAPTER={chapter}
ROOT="${{AUTOGRADER_ROOT:-/autograder}}"
PYTHON="$ROOT/venv/bin/python"
test -x "$PYTHON" || PYTHON="$(command -v python3)"
mkdir -p "$ROOT/results"
mapfile -t FOUND < <(find "$ROOT/submission" -name '*.ipynb' -not -path '*/.ipynb_checkpoints/*' | sort)
if test "${{#FOUND[@]}}" -ne 1; then
  # not graded: the student reads why, and may submit again
  "$PYTHON" - "$ROOT/results/results.json" "$CHAPTER" "${{#FOUND[@]}}" <<'EOF'
import json, sys
path, chapter, count = sys.argv[1], sys.argv[2], sys.argv[3]
message = (f"Not graded: upload exactly one notebook, your {{chapter}}.ipynb; this submission has {{count}} "
           "notebooks (.ipynb files).")
json.dump({{"score": 0.0, "output": message, "tests": []}}, open(path, "w"), indent=2)
EOF
  exit 0
fi
# the template course setup.sh made, if it did (without it, the chapter is assigned for the submission)
TEMPLATE=()
test -f "$ROOT/template/course/gradebook.db" && TEMPLATE=(--template "$ROOT/template/course")
# from source/, so that the tools and the course are the zip's (python -m: this folder first on sys.path)
cd "$ROOT/source" || exit 1
exec "$PYTHON" -m tools.grading.grade_submission "$CHAPTER" "${{FOUND[0]}}" --out "$ROOT/results" \
  ${{TEMPLATE[@]+"${{TEMPLATE[@]}}"}} \
  --memory {memory} --cpu-seconds {cpu_seconds} --max-processes {max_processes}
'''


def tracked(folder: str) -> list[Path]:
    """The files of ``folder`` tracked by git, as paths relative to the repository."""
    out = subprocess.run(["git", "ls-files", "-z", "--", folder], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout
    return [Path(name) for name in out.split("\0") if name and (ROOT / name).is_file()]


def contents(chapter: str) -> list[Path]:
    """The repository files that go into the autograder of ``chapter``, relative to the repository."""
    files = [path for folder in FOLDERS for path in tracked(folder)]
    return sorted({*files, *(Path(name) for name in FILES), Path("notebooks") / f"{chapter}.ipynb"})


def _add(archive: zipfile.ZipFile, name: str, data: bytes, executable: bool = False) -> None:
    info = zipfile.ZipInfo(name, date_time=(2020, 1, 1, 0, 0, 0))
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = (0o100755 if executable else 0o100644) << 16
    archive.writestr(info, data)


def write_zip(chapter: str, out: Path, memory_mib: int = DEFAULT_MEMORY_MIB,
              cpu_seconds: int = DEFAULT_CPU_SECONDS, max_processes: int = GRADESCOPE_MAX_PROCESSES) -> Path:
    """Write the autograder of ``chapter`` to ``out``; return ``out``.

    ``memory_mib``, ``cpu_seconds`` and ``max_processes`` are the caps ``run_autograder`` passes
    to ``grade_submission.py`` (``--memory``, ``--cpu-seconds``, ``--max-processes``; 0 processes:
    no cap, :data:`GRADESCOPE_MAX_PROCESSES`). Raises ``FileNotFoundError`` naming the chapter when
    ``notebooks/<chapter>.ipynb`` does not exist, and ``ValueError`` when the memory or CPU cap is
    not positive or ``max_processes`` is negative.
    """
    if not (ROOT / "notebooks" / f"{chapter}.ipynb").is_file():
        chapters = sorted(p.stem for p in (ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
        raise FileNotFoundError(f"chapter: no notebook notebooks/{chapter}.ipynb (chapters: {', '.join(chapters)})")
    if memory_mib <= 0 or cpu_seconds <= 0:
        raise ValueError(f"memory_mib and cpu_seconds must be positive; got {memory_mib} and {cpu_seconds}")
    if max_processes < 0:
        raise ValueError(f"max_processes must be 0 (no cap) or a positive number of processes; got {max_processes}")
    out.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(out, "w") as archive:
        _add(archive, "setup.sh", SETUP.encode(), executable=True)
        _add(archive, "run_autograder", RUN.format(chapter=chapter, memory=memory_mib, cpu_seconds=cpu_seconds,
                                                   max_processes=max_processes).encode(), executable=True)
        for path in contents(chapter):
            _add(archive, path.as_posix(), (ROOT / path).read_bytes(), executable=path.suffix == ".py"
                 and path.parts[0] == "tools")
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog="The zip holds the chapter's solutions: it is the instructor's.")
    parser.add_argument("chapter", help="the chapter, e.g. 03_three_rpr")
    parser.add_argument("--out", type=Path, default=None,
                        help="the zip to write (default: _build/gradescope/<chapter>.zip)")
    add_cap_options(parser, GRADESCOPE_MAX_PROCESSES,
                    "processes and threads of the submission's kernel (default "
                    f"{GRADESCOPE_MAX_PROCESSES}: no cap, Gradescope's container is the cap, since as root "
                    f"the cap needs a writable pids cgroup; {DEFAULT_MAX_PROCESSES} where the container gives one)")
    args = parser.parse_args(argv)
    out = args.out or ROOT / "_build" / "gradescope" / f"{args.chapter}.zip"
    try:
        write_zip(args.chapter, out.resolve(), args.memory, args.cpu_seconds, args.max_processes)
    except (FileNotFoundError, ValueError) as error:
        print(f"ERROR [gradescope]: {error}", file=sys.stderr)
        return 2
    print(f"The Gradescope autograder of {args.chapter}: {out}\n"
          "Upload it on the assignment's 'Configure Autograder' page. It holds the chapter's solutions "
          "and hidden tests: keep it to the course's staff, never give it to students.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
