"""Grading on other engines: Gradescope's autograder, ``make grade``'s jobs, a Kubernetes Job.

One chapter (:data:`CHAPTER`, chapter 7: its cells run in under a second, so that a graded
submission costs about 5 CPU-s, chapter 3's about 27) is graded end to end:

* ``run_autograder`` from the zip ``make gradescope`` writes (tools/grading/gradescope.py), unpacked
  in temporary ``/autograder``-shaped folders (``AUTOGRADER_ROOT`` set, the venv's python on
  PATH), grades a correct, a blank, a typical-mistake and a tampering submission, each in a
  folder of its own and all at once (as Gradescope, one container per submission); each
  test's score is the one ``nbgrader autograde`` gives in the chapter's shared course
  (tests/support/grading_course.py: its ``correct``, ``unanswered`` and ``mistake``; the tampering
  submission is a blank one with forged verdicts, which the tamper suite,
  tests/test_grading_tamper.py, shows scores what the blank scores);
* ``tools/grading/grade_many.py`` (``make grade``) with two jobs grades the typical mistake again and
  a correct submission with two incidents: the mistake scores what it scored alone;
  - 8 GB allocated in an ungraded cell of the student's own, after the first test: the
    allocation fails (``MemoryError`` in its feedback) and costs no mark;
  - a fork bomb at the top of the last answer cell: it gets ``BlockingIOError`` at the cap on
    the kernel's processes; its children stay counted until the kernel ends, so the kernel
    left at its cap is restarted: that task's tests lose their points, the others keep theirs,
    grading returns and no process of the bomb is left.
  The two are independent (the allocation is in an ungraded cell, so it can change no score,
  the bombed task's included) and are graded in one submission, not two (a grading costs about
  10 CPU-s). The same submission's last ungraded cell, after every graded one, ends in a loop
  that never ends: the student's kernel stops after the last graded cell, so it is not run (no
  time limit is waited for) and the page says why that cell has no output.

The rest is cheap: the zip holds what grading needs and no other chapter, ``run_autograder``
explains a submission without exactly one notebook, the cap on processes (``--max-processes``,
``make gradescope|grade MAX_PROCESSES=``) reaches run_autograder's command and each of
grade_many's and grade_shard's gradings, a kernel's count under the cap holds the children it
has not reaped (zombies) and one left without room is found, the Kubernetes manifests are valid
against the Kubernetes schema (kubernetes-validate), and the Containerfile (which cannot be
built here: no container engine) parses and installs what ``run_autograder`` needs.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
import subprocess
import sys
import time
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from conftest import ROOT
from support import grading_course
from support.benign_variants import HANG, with_incident, with_own_cell
from support.tampering import tampered
from support.nbgrader_course import correct_submission, mistaken_submission, save
from tools.grading import grade_many, grade_submission, gradescope, process_cap
from tools.grading.deploy import grade_shard

#: the chapter graded here: the everyday chapter (tests/support/tiers.py), chapter 7, the cheapest
#: to grade (about 5 CPU-s per submission; benchmarks/README.md)
CHAPTER = grading_course.EVERYDAY_CHAPTER
DEPLOY = ROOT / "tools" / "grading" / "deploy"
#: a correct submission's experiment, in an ungraded cell: 8 GB of address space (np.empty maps it
#: without writing it: were the cap missing, the test would not fill the machine's memory either)
ALLOCATE_8GB = ("import numpy as np\n\nblock = np.empty(8 * 1024**3, dtype=np.uint8)  # 8 GB\n"
                "print('allocated', block.nbytes)\n")
#: a fork bomb, bounded so that it cannot harm the machine were the cap missing: at most 2,000
#: children, each ending at once (a zombie until the kernel ends: a process, no memory), named
#: so that one left behind can be found
FORK_BOMB = ('import os\n\nforked = 0\nwhile forked < 2000:\n    if os.fork() == 0:\n'
             '        with open("/proc/self/comm", "w") as name:\n            name.write("rkforkbomb")\n'
             '        os._exit(0)\n    forked += 1\nprint("forked", forked)\n\n')


def _bomb_processes() -> list[int]:
    """Processes named by FORK_BOMB, anywhere on the machine."""
    found = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and (entry / "comm").read_text().strip() == "rkforkbomb":
                found.append(int(entry.name))
        except OSError:   # ended meanwhile
            continue
    return found


#: the submissions run_autograder grades, and the nbgrader student whose scores each must get
AUTOGRADED = {"correct": "correct", "blank": "unanswered", "mistake": "mistake", "tampering": "unanswered"}
#: the submissions grade_many grades, two at a time
GRADED_MANY = ("mistake", "incidents")


def _chapter_run(request, tmp_path_factory):
    run = grading_course.graded_courses(request, tmp_path_factory)[CHAPTER]
    if run.error:
        pytest.fail(run.fail_message())
    return run


def submissions(run) -> dict[str, dict]:
    """The notebooks graded here, made from the chapter's shared run (its release and source)."""
    correct = correct_submission(run.release, run.source)
    assert run.mistake is not None, f"{CHAPTER} has no typical mistake robokin.check recognises"
    return {"correct": correct, "blank": run.release, "mistake": mistaken_submission(correct, run.mistake),
            "tampering": tampered(run.release, "forged_check"), "incidents": with_incidents(correct)}


def bombed_answer(nb: dict) -> dict:
    """The cell of ``nb`` that :func:`with_incidents` starts with the fork bomb: its last answer cell."""
    return [cell for cell in nb["cells"] if cell.get("metadata", {}).get("nbgrader", {}).get("solution")][-1]


def with_incidents(correct: dict) -> dict:
    """``correct`` with :data:`FORK_BOMB` at the top of its last answer cell, :data:`ALLOCATE_8GB` in
    an ungraded cell of the student's own after the first test (so that the allocation can change
    no score, and the bomb's loss is the bomb's alone), and benign_variants' endless ``HANG`` at
    the end of its last ungraded cell, which must come after every graded one (it is not run)."""
    nb = with_incident(with_own_cell(correct, ALLOCATE_8GB), HANG)
    cells = nb["cells"]
    hanging = next(index for index, cell in enumerate(cells) if HANG in "".join(cell["source"]))
    grading = [cell.get("metadata", {}).get("nbgrader", {}) for cell in cells]
    last_graded = max(index for index, info in enumerate(grading) if info.get("grade") or info.get("solution"))
    assert hanging > last_graded, f"{CHAPTER}: the endless cell ({hanging}) is before a graded cell"
    bombed = bombed_answer(nb)
    bombed["source"] = FORK_BOMB + "".join(bombed["source"])
    return nb


def autograder_folder(archive: Path, base: Path) -> Path:
    """An ``/autograder``-shaped folder in ``base``: the zip ``archive`` in ``source/``,
    ``run_autograder`` beside it."""
    root = base / "autograder"
    with zipfile.ZipFile(archive) as unpacked:
        unpacked.extractall(root / "source")
        for info in unpacked.infolist():   # extractall drops the modes
            (root / "source" / info.filename).chmod((info.external_attr >> 16) & 0o777)
    shutil.copy2(root / "source" / "run_autograder", root / "run_autograder")
    return root


def run_autograder(root: Path, notebooks: dict[str, dict]) -> tuple[subprocess.CompletedProcess, dict]:
    """``root/run_autograder`` on a submission folder holding ``notebooks``, as Gradescope runs it."""
    for folder in ("submission", "results"):
        shutil.rmtree(root / folder, ignore_errors=True)
        (root / folder).mkdir()
    for name, nb in notebooks.items():
        save(nb, root / "submission" / name)
    env = dict(os.environ, AUTOGRADER_ROOT=str(root),
               PATH=os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")]))
    proc = subprocess.run([str(root / "run_autograder")], env=env, capture_output=True, text=True, timeout=1200)
    results = root / "results" / "results.json"
    return proc, json.loads(results.read_text(encoding="utf-8")) if results.is_file() else {}


def scores(results: dict) -> dict[str, float]:
    return {test["name"]: test["score"] for test in results.get("tests", [])}


@pytest.fixture(scope="module")
def graded(request, tmp_path_factory):
    """The chapter's shared nbgrader run, and every submission here graded by run_autograder (each
    in an ``/autograder`` folder of its own, all at once, as Gradescope grades each submission in a
    container of its own) while grade_many grades two more with two jobs:
    ``(run, {how: {submission: results}}, logs)``."""
    run = _chapter_run(request, tmp_path_factory)
    made = submissions(run)
    base = tmp_path_factory.mktemp("engines")
    archive = gradescope.write_zip(CHAPTER, base / "autograder.zip")
    folder = base / "submissions"
    for name in GRADED_MANY:
        save(made[name], folder / name / f"{CHAPTER}.ipynb")
    assert not _bomb_processes(), "processes of an earlier fork bomb are running: cannot tell this one's"

    def autograde(name: str):
        started = time.perf_counter()
        proc, results = run_autograder(autograder_folder(archive, base / name), {f"{CHAPTER}.ipynb": made[name]})
        return results, (f"run_autograder {name}: exit {proc.returncode}, {time.perf_counter() - started:.0f} s\n"
                         f"{proc.stdout}{proc.stderr[-3000:]}")

    def grade_many():
        proc = subprocess.run([sys.executable, str(ROOT / "tools" / "grading" / "grade_many.py"), CHAPTER, str(folder),
                               "--jobs", "2"], capture_output=True, text=True, timeout=1800)
        return proc, _bomb_processes()   # the bomb's processes left once its grading returned

    with ThreadPoolExecutor(max_workers=len(AUTOGRADED) + 1) as pool:
        autograded = {name: pool.submit(autograde, name) for name in AUTOGRADED}
        many = pool.submit(grade_many)
        out: dict[str, dict[str, dict]] = {"autograder": {}, "grade_many": {}}
        logs = []
        for name, future in autograded.items():
            out["autograder"][name], log = future.result()
            logs.append(log)
        proc, left = many.result()
    logs.append(f"grade_many --jobs 2: exit {proc.returncode}\n{proc.stdout}{proc.stderr[-3000:]}")
    for name in GRADED_MANY:
        results = folder / name / "results.json"
        out["grade_many"][name] = json.loads(results.read_text(encoding="utf-8")) if results.is_file() else {}
        page = folder / name / "feedback.html"
        out["grade_many"][name]["feedback"] = page.read_text(encoding="utf-8") if page.is_file() else ""
    out["grade_many"]["incidents"]["bomb_processes_left"] = left
    print("\n" + "\n".join(line.splitlines()[0] + " " + line.splitlines()[-1] for line in logs if line.strip()))
    return run, out, "\n".join(logs)


# ---------------------------------------------------------------- graded: run_autograder, grade_many
@grading_course.reads(CHAPTER)
@pytest.mark.parametrize("submission", list(AUTOGRADED))
def test_run_autograder_gives_the_nbgrader_scores(graded, submission):
    run, out, logs = graded
    results = out["autograder"][submission]
    assert results, f"run_autograder wrote no results.json for {submission}:\n{logs}"
    expected = run.scores[AUTOGRADED[submission]]
    assert scores(results) == pytest.approx(expected), (submission, logs[-3000:])
    assert results["score"] == pytest.approx(sum(expected.values()))
    assert {test["name"]: test["max_score"] for test in results["tests"]} == pytest.approx(run.maximum)
    if submission == "correct":
        assert results["score"] == pytest.approx(sum(run.maximum.values()))
    if submission == "mistake":
        assert 0 < results["score"] < sum(run.maximum.values())


@grading_course.reads(CHAPTER)
def test_results_json_is_gradescopes_format_and_hides_hidden_tests(graded):
    run, out, _ = graded
    results = out["autograder"]["mistake"]
    assert set(results) >= {"score", "tests"}
    for test in results["tests"]:
        assert set(test) >= {"name", "score", "max_score", "output"} and isinstance(test["output"], str)
    failed = [test for test in results["tests"] if test["score"] < test["max_score"]]
    assert failed and all(test["output"] for test in failed), failed
    assert "### BEGIN HIDDEN TESTS" not in json.dumps(results) and "Traceback" not in json.dumps(results)


@grading_course.reads(CHAPTER)
def test_two_jobs_give_the_scores_of_run_autograder(graded):
    _, out, logs = graded
    assert out["grade_many"]["mistake"].get("tests"), logs
    assert scores(out["grade_many"]["mistake"]) == scores(out["autograder"]["mistake"])


def _incidents(graded) -> tuple[dict, dict[str, float], str, str]:
    """grade_many's results of the submission with both incidents, the scores it must get (the
    bombed task's tests 0, every other test its full marks: the allocation, after every graded
    test, can change none), its feedback as text, and the logs."""
    run, out, logs = graded
    results = out["grade_many"]["incidents"]
    task = bombed_answer(run.source)["metadata"]["robokin"]["task"]
    tasks = {cell["metadata"]["nbgrader"]["grade_id"]: cell["metadata"]["robokin"]["task"]
             for cell in run.source["cells"] if cell.get("metadata", {}).get("nbgrader", {}).get("grade")}
    assert task in tasks.values(), f"the bombed task {task} has no graded test"
    expected = {name: 0.0 if tasks[name] == task else points for name, points in run.maximum.items()}
    assert expected == {name: 0.0 if tasks[name] == task else score for name, score in run.scores["correct"].items()}
    text = " ".join(re.sub(r"<[^>]+>", " ", results.get("feedback", "")).split())
    return results, expected, text, logs


@grading_course.reads(CHAPTER)
def test_allocating_8_gb_fails_and_keeps_the_other_marks(graded):
    results, expected, text, logs = _incidents(graded)
    assert scores(results) == pytest.approx(expected), logs
    # the report's note on the incident, and nothing printed after the allocation
    assert re.search(r"raised MemoryError ?: Unable to allocate 8\.00 GiB", text), logs
    assert "allocated 8589934592" not in text


@grading_course.reads(CHAPTER)
def test_a_loop_after_the_last_graded_cell_is_not_run(graded):
    """The endless loop after every graded cell is not run (nothing there is graded): no time limit
    is waited for, no incident is reported, and the page says once why the cells have no output."""
    from tools.grading.robokin_nbgrader.not_run_note import TITLE

    results, expected, text, logs = _incidents(graded)
    assert scores(results) == pytest.approx(expected), logs
    assert "my experiment never ends" in text, "the endless cell is not shown (the test tests nothing)"
    assert "ran longer than the time limit" not in text and text.count(TITLE) == 1, text[:3000]


@grading_course.reads(CHAPTER)
def test_a_fork_bomb_loses_its_cell_and_leaves_no_process(graded):
    results, expected, text, logs = _incidents(graded)
    left = results["bomb_processes_left"]
    assert not left, f"{len(left)} processes of the fork bomb are left after grading: {left[:10]}"
    assert "BlockingIOError" in text and "forked 2000" not in text, "the fork was not stopped by the cap"
    # the kernel, left at its cap by the bomb's children, was restarted and the notebook went on
    assert "left the kernel at its cap on processes" in text and "The kernel was restarted" in text, text[:2000]
    # the bombed task's tests lose their points; every other test keeps its own
    for test in results["tests"]:
        assert test["score"] == pytest.approx(expected[test["name"]]), (test, results["output"], logs[-3000:])
    assert 0 in expected.values()


# ---------------------------------------------------------------- cheap: the zip, the manifests
def test_zip_holds_what_grading_needs_and_no_other_chapter(tmp_path):
    archive = gradescope.write_zip(CHAPTER, tmp_path / "a.zip")
    with zipfile.ZipFile(archive) as unpacked:
        names = set(unpacked.namelist())
        modes = {info.filename: info.external_attr >> 16 for info in unpacked.infolist()}
        setup = unpacked.read("setup.sh").decode()
        run = unpacked.read("run_autograder").decode()
    assert {"setup.sh", "run_autograder", "nbgrader_config.py", "pyproject.toml", "requirements.txt",
            "constraints.txt", "book/references.bib", "tools/grading/grade_submission.py", "robokin/__init__.py",
            "tools/__init__.py", "tools/notebook_analysis.py", "tools/kernel_sockets.py",
            f"notebooks/{CHAPTER}.ipynb"} <= names
    assert not [name for name in names if name.startswith("tools/authoring/")], "the zip carries authoring scripts"
    assert [name for name in names if name.startswith("notebooks/")] == [f"notebooks/{CHAPTER}.ipynb"]
    assert not [name for name in names if "__pycache__" in name or name.startswith(("tests/", "_build/"))]
    assert modes["setup.sh"] & stat.S_IXUSR and modes["run_autograder"] & stat.S_IXUSR
    assert "bubblewrap" in setup and "pip install -r requirements.txt" in setup
    # the chapter assigned once at set-up, in the template course run_autograder copies for each submission
    assert setup.rstrip().endswith('-m tools.grading.grade_submission "$CHAPTER" --assign "$ROOT/template"'), setup
    assert '(--template "$ROOT/template/course")' in run and 'TEMPLATE[@]+"${TEMPLATE[@]}"' in run, run


def test_a_template_that_is_not_an_assigned_course_is_refused(tmp_path):
    (tmp_path / "template" / "source" / CHAPTER).mkdir(parents=True)
    with pytest.raises(FileNotFoundError, match=r"^template must be a course in which .* no gradebook\.db, release/"):
        grade_submission.grade(CHAPTER, tmp_path / "any.ipynb", tmp_path / "out", template=tmp_path / "template")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("chapter, memory", [("99_no_such_chapter", 4096), (CHAPTER, 0)])
def test_zip_refuses_bad_arguments(tmp_path, chapter, memory):
    with pytest.raises((FileNotFoundError, ValueError), match="chapter" if memory else "memory_mib"):
        gradescope.write_zip(chapter, tmp_path / "a.zip", memory_mib=memory)


@pytest.mark.parametrize("argv, expected", [([], 0), (["--max-processes", "256"], 256)])
def test_run_autograder_passes_the_process_cap(tmp_path, argv, expected):
    """gradescope.py's ``--max-processes`` (``make gradescope MAX_PROCESSES=``) is run_autograder's; by
    default 0, Gradescope's container being the cap (root there has no writable pids cgroup)."""
    assert gradescope.GRADESCOPE_MAX_PROCESSES == 0
    assert gradescope.main([CHAPTER, "--out", str(tmp_path / "a.zip"), *argv]) == 0
    with zipfile.ZipFile(tmp_path / "a.zip") as unpacked:
        script = unpacked.read("run_autograder").decode()
    command = script[script.index("-m tools.grading.grade_submission"):]
    assert re.search(rf"--max-processes {expected}\n", command), command
    assert f"--memory {grade_submission.DEFAULT_MEMORY_MIB} --cpu-seconds {grade_submission.DEFAULT_CPU_SECONDS}" \
        in command


def test_zip_refuses_a_negative_process_cap(tmp_path, capsys):
    with pytest.raises(ValueError, match=r"max_processes must be 0 \(no cap\) or a positive.*got -1"):
        gradescope.write_zip(CHAPTER, tmp_path / "a.zip", max_processes=-1)
    assert gradescope.main([CHAPTER, "--out", str(tmp_path / "a.zip"), "--max-processes", "-1"]) == 2
    assert "max_processes" in capsys.readouterr().err and not (tmp_path / "a.zip").exists()


@pytest.mark.parametrize("argv, expected", [([], process_cap.DEFAULT_MAX_PROCESSES), (["--max-processes", "0"], 0)])
def test_grade_many_passes_the_process_cap_on(tmp_path, monkeypatch, argv, expected):
    """grade_many.py's ``--max-processes`` (``make grade MAX_PROCESSES=``) reaches each submission's grading,
    and so does the template course, made once per run."""
    for student in ("alice", "bob"):
        save({"cells": []}, tmp_path / student / f"{CHAPTER}.ipynb")
    seen, assigned = [], []

    def grade(chapter, notebook, out, memory_mib, cpu_seconds, max_processes, template):
        seen.append((notebook.parent.name, max_processes, template))
        return {"score": 1.0, "tests": [{"max_score": 2.0}]}

    monkeypatch.setattr(grade_many, "grade", grade)
    def assign(chapter: str, folder: Path) -> Path:
        assigned.append(folder)
        return folder / "course"

    monkeypatch.setattr(grade_many, "assign", assign)
    assert grade_many.main([CHAPTER, str(tmp_path), "--jobs", "1", *argv]) == 0
    assert len(assigned) == 1
    assert sorted(seen) == [("alice", expected, assigned[0] / "course"), ("bob", expected, assigned[0] / "course")]


def test_grade_many_refuses_a_negative_process_cap(tmp_path, capsys):
    save({"cells": []}, tmp_path / "alice" / f"{CHAPTER}.ipynb")
    assert grade_many.main([CHAPTER, str(tmp_path), "--max-processes", "-1"]) == 2
    assert "--max-processes must be 0 (no cap) or a positive number of processes; got -1" in capsys.readouterr().err
    assert not (tmp_path / "alice" / "results.json").exists()


@pytest.mark.parametrize("target, tool", [("grade", "grade_many.py"), ("gradescope", "gradescope.py")])
def test_make_passes_max_processes_on(target, tool):
    """``make grade|gradescope MAX_PROCESSES=n`` runs the tool with ``--max-processes n``, and without
    the variable the tool's own default (``make -n``: the commands, none run)."""
    args = ["make", "-n", "-o", ".venv/.installed", target, "CH=" + CHAPTER, "SUBMISSIONS=folder"]
    commands = {}
    for extra in ([], ["MAX_PROCESSES=0"]):
        proc = subprocess.run(args + extra, cwd=ROOT, capture_output=True, text=True, timeout=60)
        assert proc.returncode == 0, proc.stderr
        lines = proc.stdout.replace("\\\n", " ").splitlines()   # a recipe's continued lines as one
        commands[bool(extra)] = next(line for line in lines if tool in line)
    assert "--max-processes" not in commands[False]
    assert commands[True].rstrip().endswith("--max-processes 0"), commands[True]


@pytest.mark.parametrize("notebooks", [0, 2])
def test_run_autograder_explains_a_submission_without_one_notebook(tmp_path, notebooks):
    root = autograder_folder(gradescope.write_zip(CHAPTER, tmp_path / "autograder.zip"), tmp_path)
    proc, results = run_autograder(root, {f"{k}.ipynb": {"cells": []} for k in range(notebooks)})
    assert proc.returncode == 0, proc.stderr
    assert results["score"] == 0 and results["tests"] == []
    assert f"upload exactly one notebook, your {CHAPTER}.ipynb" in results["output"]
    assert f"has {notebooks} notebooks" in results["output"]


def test_manifests_validate_against_the_kubernetes_schema():
    kubernetes_validate = pytest.importorskip("kubernetes_validate")
    import yaml

    documents = [doc for path in sorted(DEPLOY.glob("*.yaml"))
                 for doc in yaml.safe_load_all(path.read_text(encoding="utf-8")) if doc]
    kinds = {doc["kind"] for doc in documents}
    assert "Job" in kinds, kinds
    for doc in documents:
        kubernetes_validate.validate(doc, "1.33.0", strict=True)
    job = next(doc for doc in documents if doc["kind"] == "Job")
    misspelt = {**job, "spec": {**job["spec"], "completionsMode": "Indexed"}}
    with pytest.raises(kubernetes_validate.ValidationError, match="completionsMode"):   # the check checks
        kubernetes_validate.validate(misspelt, "1.33.0", strict=True)
    spec = job["spec"]
    assert spec["completionMode"] == "Indexed" and spec["completions"] >= 1
    for container in spec["template"]["spec"]["containers"]:
        resources = container["resources"]
        assert {"cpu", "memory"} <= set(resources["requests"]) and {"cpu", "memory"} <= set(resources["limits"])
        command = " ".join(container.get("command", []) + container.get("args", []))
        assert "grade_shard.py" in command or "grade_many.py" in command, command


@pytest.mark.parametrize("students, shards", [(0, 3), (1, 3), (7, 3), (9, 3), (5, 1), (20, 8)])
def test_shards_grade_every_student_once(students, shards):
    found = [Path(f"s{k:02d}") / f"{CHAPTER}.ipynb" for k in range(students)]
    dealt = [grade_shard.shard(found, index, shards) for index in range(shards)]
    assert sorted(path for one in dealt for path in one) == found
    assert max(map(len, dealt)) - min(map(len, dealt)) <= 1


@pytest.mark.parametrize("index, shards, name", [(0, 0, "shards"), (3, 3, "index"), (-1, 2, "index")])
def test_shard_refuses_bad_arguments(index, shards, name):
    with pytest.raises(ValueError, match=f"^{name} must"):
        grade_shard.shard([], index, shards)


@pytest.mark.parametrize("argv, expected", [([], process_cap.DEFAULT_MAX_PROCESSES), (["--max-processes", "0"], 0),
                                            (["--max-processes", "64"], 64)])
def test_grade_shard_passes_the_process_cap_on(tmp_path, monkeypatch, argv, expected):
    """grade_shard.py's ``--max-processes`` reaches the grading of each student of its shard, and so does
    the template course, made once per shard."""
    for student in ("alice", "bob", "carol"):
        save({"cells": []}, tmp_path / student / f"{CHAPTER}.ipynb")
    seen, assigned = [], []

    def grade_one(chapter, notebook, memory_mib, cpu_seconds, max_processes, template):
        seen.append((notebook.parent.name, max_processes, template))
        return notebook, "1 / 2", True

    monkeypatch.setattr(grade_many, "grade_one", grade_one)
    def assign(chapter: str, folder: Path) -> Path:
        assigned.append(folder)
        return folder / "course"

    monkeypatch.setattr(grade_many, "assign", assign)
    assert grade_shard.main([CHAPTER, str(tmp_path), "--shards", "2", "--index", "0", "--jobs", "1", *argv]) == 0
    assert len(assigned) == 1
    assert sorted(seen) == [("alice", expected, assigned[0] / "course"), ("carol", expected, assigned[0] / "course")]


def test_grade_shard_refuses_a_negative_process_cap(tmp_path, monkeypatch, capsys):
    save({"cells": []}, tmp_path / "alice" / f"{CHAPTER}.ipynb")
    monkeypatch.setattr(grade_many, "grade_one", lambda *args: pytest.fail("graded despite a bad cap"))
    assert grade_shard.main([CHAPTER, str(tmp_path), "--shards", "1", "--index", "0", "--max-processes", "-1"]) == 2
    assert "--max-processes must be 0 (no cap) or a positive number of processes; got -1" in capsys.readouterr().err


def containerfile_instructions(text: str) -> list[tuple[str, str]]:
    """``[(INSTRUCTION, arguments)]`` of a Containerfile: comments dropped, continued lines joined."""
    out, pending = [], ""
    for line in text.splitlines():
        if not pending and (not line.strip() or line.lstrip().startswith("#")):
            continue
        pending += line.rstrip()
        if pending.endswith("\\"):
            pending = pending[:-1] + " "
            continue
        word, _, rest = pending.strip().partition(" ")
        out.append((word, " ".join(rest.split())))
        pending = ""
    assert not pending, "the Containerfile ends in a continued line"
    return out


def test_containerfile_parses_and_installs_what_run_autograder_needs():
    instructions = containerfile_instructions((DEPLOY / "Containerfile").read_text(encoding="utf-8"))
    known = {"FROM", "RUN", "COPY", "ADD", "ENV", "ARG", "WORKDIR", "USER", "LABEL", "ENTRYPOINT", "CMD"}
    assert instructions[0][0] in {"FROM", "ARG"} and {word for word, _ in instructions} <= known, instructions
    base = next(rest for word, rest in instructions if word == "FROM")
    assert base.startswith(("debian:", "ubuntu:", "python:")), base
    runs = " ".join(rest for word, rest in instructions if word == "RUN")
    assert "bubblewrap" in runs and "pip install" in runs and "-r requirements.txt" in runs, runs
    copied = " ".join(rest for word, rest in instructions if word in {"COPY", "ADD"})
    for needed in ("robokin", "tools", "nbgrader_config.py", "requirements.txt", "constraints.txt", "pyproject.toml"):
        assert needed in copied, f"the image lacks {needed}: {copied}"


# ---------------------------------------------------------------- the cap on a kernel's processes
def _zombie() -> subprocess.Popen:
    """A child that has ended and is not reaped yet (a zombie)."""
    child = subprocess.Popen(["true"])
    deadline = time.monotonic() + 10
    while Path(f"/proc/{child.pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z":
        assert time.monotonic() < deadline, "the child did not end"
        time.sleep(0.001)
    return child


def test_a_child_counts_under_the_cap_until_it_is_reaped():
    before = process_cap.tasks_of_tree(os.getpid())
    child = _zombie()
    try:
        assert process_cap.tasks_of_tree(os.getpid()) == before + 1
    finally:
        child.wait()
    assert process_cap.tasks_of_tree(os.getpid()) == before
    assert process_cap.tasks_of_tree(child.pid) == 0   # reaped: no process left


def test_a_kernel_without_room_under_its_cap_is_found(tmp_path):
    used = process_cap.tasks_of_tree(os.getpid())
    roomy = process_cap.ProcessCap("rlimit", used + process_cap.HEADROOM)
    assert roomy.full(os.getpid()) == ""
    child = _zombie()   # one more in the tree: one place too few left
    try:
        assert f"({used + 1} processes and threads of {used + process_cap.HEADROOM}:" in roomy.full(os.getpid())
    finally:
        child.wait()
    # a cgroup's own count, pids.current, is the one read where there is a cgroup
    (tmp_path / "pids.current").write_text("250\n")
    capped = process_cap.ProcessCap("cgroup", 256, cgroup=tmp_path)
    assert capped.tasks(os.getpid()) == 250 and "(250 processes and threads of 256:" in capped.full(os.getpid())
    (tmp_path / "pids.current").write_text(f"{256 - process_cap.HEADROOM}\n")
    assert capped.full(os.getpid()) == ""


def test_a_cell_that_leaves_the_kernel_at_its_cap_loses_the_kernel(monkeypatch):
    """After each cell the grader asks the kernel's manager; a kernel at its cap is lost as one that
    died in the cell (restarted, the cells before run again), and the report says why."""
    from nbconvert.preprocessors import ExecutePreprocessor
    from nbformat.v4 import new_code_cell, new_notebook
    from tools.grading.bridge.execute import BridgedExecute
    from tools.grading.robokin_nbgrader import GradingIncidents
    from tools.grading.sandbox import SandboxedKernelManager

    why = "the cell left the kernel at its cap on processes (256 processes and threads of 256: ...)"
    monkeypatch.setattr(ExecutePreprocessor, "preprocess_cell", lambda self, cell, resources, index: (cell, resources))
    monkeypatch.setattr(SandboxedKernelManager, "at_process_cap", lambda self: why)
    monkeypatch.setattr(BridgedExecute, "_restart_and_replay", lambda self, index: True)
    execute = BridgedExecute()
    bomb, test = new_code_cell("fork_bomb()"), new_code_cell("assert answer() == 1", metadata={"nbgrader": {
        "grade": True, "solution": False, "points": 2, "grade_id": "task5_test1", "schema_version": 3}})
    execute.nb, execute.km = new_notebook(cells=[bomb, test]), SandboxedKernelManager(writable="/tmp")
    execute._stopped, execute._replays, execute._last_code, execute._last_graded = None, 0, 1, 1
    execute._report = {"incidents": []}
    execute.preprocess_cell(bomb, {}, 0)
    assert execute._stopped is None and execute._replays == 1   # restarted: grading goes on
    assert bomb.outputs[-1]["text"] == f"KernelLost: {why}: the kernel was killed\n"
    nb, _ = GradingIncidents().preprocess(new_notebook(cells=[bomb]), {"robokin": execute._report})
    assert f"(not graded): {why}; the kernel was killed. The kernel was restarted" in nb.cells[0].source


def _no_cap_here(monkeypatch):
    monkeypatch.setattr(process_cap, "cgroup_parent", lambda: (None, "/sys/fs/cgroup is read-only"))
    monkeypatch.setattr(process_cap, "exempt_from_rlimit",
                        lambda: "the grader runs as root (uid 0 of the initial user namespace)")


def test_grading_stops_naming_the_cause_when_no_cap_can_be_made(tmp_path, monkeypatch):
    _no_cap_here(monkeypatch)
    monkeypatch.delenv("ROBOKIN_GRADING_SANDBOX", raising=False)
    monkeypatch.delenv(process_cap.METHOD_VARIABLE, raising=False)
    with pytest.raises(RuntimeError, match=r"(?s)cannot cap the processes.*read-only.*runs as root.*--max-processes 0"):
        grade_submission.grade(CHAPTER, tmp_path / "any.ipynb", tmp_path / "out")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("sandbox, cause", [("on", "max_processes=0"), ("off", "ROBOKIN_GRADING_SANDBOX=off")])
def test_no_cap_is_a_logged_warning(monkeypatch, caplog, sandbox, cause):
    _no_cap_here(monkeypatch)
    monkeypatch.setenv("ROBOKIN_GRADING_SANDBOX", sandbox)
    with caplog.at_level("WARNING", logger="robokin.grading"):
        env = grade_submission.process_cap_environment(0 if sandbox == "on" else 256)
    assert process_cap.TAG_VARIABLE not in env and env.get(process_cap.VARIABLE, "0") == "0"
    assert [record.levelname for record in caplog.records] == ["WARNING"]
    assert "not capped" in caplog.text and cause in caplog.text


def test_an_ordinary_user_gets_rlimit_nproc(monkeypatch):
    monkeypatch.setattr(process_cap, "cgroup_parent", lambda: (None, "not writable"))
    monkeypatch.setattr(process_cap, "exempt_from_rlimit", lambda: "")
    monkeypatch.delenv(process_cap.METHOD_VARIABLE, raising=False)
    cap = process_cap.plan(256, make=True)
    assert cap.method == "rlimit" and not cap.outer and cap.cgroup is None
    alone, shared, namespace = cap.inner[cap.inner.index("rlimit") + 1].split(":")
    # alone in the sandbox's user namespace: the cap; sharing the grader's: its processes now plus the cap
    assert int(alone) == 256 and int(shared) >= 256 + 1 and int(namespace) == os.stat("/proc/self/ns/user").st_ino
    assert cap.inner[-1] == "--" and cap.release() == 0
