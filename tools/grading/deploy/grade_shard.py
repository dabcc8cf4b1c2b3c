#!/usr/bin/env python3
"""Grade one shard of a chapter's submissions: a pod of the Kubernetes Job grade-job.yaml.

    python tools/grading/deploy/grade_shard.py 03_three_rpr /submissions/03_three_rpr --shards 8 --jobs 2
    python tools/grading/deploy/grade_shard.py 03_three_rpr folder --shards 8 --index 3   # shard 3 by hand
    python tools/grading/deploy/grade_shard.py 03_three_rpr folder --shards 8 --max-processes 0   # root

The folder holds ``<student>/<chapter>.ipynb`` as for ``make grade`` (tools/grading/grade_many.py). The
students, sorted by name, are dealt to ``--shards`` shards like cards: shard ``i`` grades
students ``i``, ``i + shards``, ``i + 2 shards``, ... (``--index``, default the
``JOB_COMPLETION_INDEX`` Kubernetes gives each pod of an indexed Job), ``--jobs`` at a time,
each into ``<student>/results.json`` and ``feedback.html`` beside its notebook. The caps of
tools/grading/grade_submission.py are passed on as they are: ``--memory``, ``--cpu-seconds`` and
``--max-processes``; the chapter is assigned once per shard, in a template course that each
submission's course is a copy of (as ``make grade`` does). The manifest's pods run as an
ordinary user, where the default process cap holds (``RLIMIT_NPROC`` in the sandbox);
``--max-processes 0`` (no cap, with a warning on every submission) is for a grader run as root
in a container whose ``/sys/fs/cgroup`` is read-only, where the container's own process limit
(a node's ``podPidsLimit``) is the cap. A student whose ``results.json`` is newer than the
notebook is skipped (a pod that is retried does not grade its shard again), unless ``--force``.
The exit code is 1 when a submission could not be graded (Kubernetes then retries the pod,
within the Job's ``backoffLimitPerIndex``), 2 for bad arguments, 0 otherwise.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from tools.grading.grade_many import add_batch_options, batch_options_error, grade_batch, submissions


def shard(found: list[Path], index: int, shards: int) -> list[Path]:
    """The notebooks of shard ``index`` of ``shards``: every ``shards``-th one from ``index``.

    Raises ``ValueError`` naming the argument when ``shards < 1`` or ``index`` is not in
    ``0 .. shards - 1``.
    """
    if shards < 1:
        raise ValueError(f"shards must be at least 1; got {shards}")
    if not 0 <= index < shards:
        raise ValueError(f"index must be in 0..{shards - 1} (one per shard); got {index}")
    return found[index::shards]


def graded_already(notebook: Path) -> bool:
    results = notebook.parent / "results.json"
    return results.is_file() and results.stat().st_mtime >= notebook.stat().st_mtime


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chapter", help="the chapter, e.g. 03_three_rpr")
    parser.add_argument("folder", type=Path, help="folder of <student>/<chapter>.ipynb")
    parser.add_argument("--shards", type=int, required=True, help="number of shards (the Job's completions)")
    parser.add_argument("--index", type=int, default=None,
                        help="this shard, 0 .. shards-1 (default: $JOB_COMPLETION_INDEX)")
    add_batch_options(parser)
    parser.add_argument("--force", action="store_true", help="grade students that have a newer results.json too")
    args = parser.parse_args(argv)
    index = args.index
    if index is None:
        value = os.environ.get("JOB_COMPLETION_INDEX", "")
        if not value.isdigit():
            print(f"ERROR: --index not given and JOB_COMPLETION_INDEX is {value!r}, not a shard number",
                  file=sys.stderr)
            return 2
        index = int(value)
    if error := batch_options_error(args):
        print(f"ERROR: {error}", file=sys.stderr)
        return 2
    try:
        mine = shard(submissions(args.folder, args.chapter), index, args.shards)
    except ValueError as error:
        print(f"ERROR: {error}", file=sys.stderr)
        return 2
    todo = [path for path in mine if args.force or not graded_already(path)]
    print(f"shard {index} of {args.shards}: {len(mine)} submissions, {len(mine) - len(todo)} graded already",
          flush=True)
    if not todo:
        return 0

    def report(done: int, notebook: Path, verdict: str, graded: bool) -> None:
        print(f"{notebook.parent.name}: {verdict}", flush=True)

    failed = grade_batch(args.chapter, todo, args, report, in_order=True)
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
