# robokin workbook — set-up, book, tests.
#
#   make book    build the book (creates .venv and installs everything on first use) from
#                the outputs stored in the notebooks: it executes nothing (make execute
#                computes them; nbval in make test fails when one differs from a fresh run)
#   make book EDITION=student   the student edition of the book (no solutions) in _build/student/
#   make student the student edition of every chapter and the nbgrader course (_build/nbgrader/)
#   make test    the everyday suite on two cores (about 4 min; same set-up on first use): unit,
#                property and fuzz tests, every notebook under nbval, both editions of the book
#                with one page of each kind in Chromium, one chapter graded end to end
#   make test-all  the complete suite, what CI runs (.ci/run): make test plus every chapter's
#                grading, the notebooks under other BLAS kernels, every page, live JupyterLab,
#                a scaffolded chapter (tests/support/tiers.py says which check is in which tier)
#   make quick   the fast inner loop: unit, property and fuzz tests only (< 1 min);
#                no notebooks, book, browser or nbgrader (CONTRIBUTING.md)
#   make lab     open the notebooks in JupyterLab with live 3D views
#   make execute re-run every notebook in a fresh kernel and store its outputs (stream
#                outputs merged, so that an unchanged notebook stores unchanged bytes);
#                make execute NB=notebooks/02_ur10_ik.ipynb re-runs that one only (the kernel
#                talks over sockets in a private folder: tools/kernel_sockets.py)
#   make test-chapter CH=03_three_rpr   one chapter's tests, that chapter alone graded (every tier)
#   make grade CH=03_three_rpr SUBMISSIONS=folder [JOBS=2]  grade <folder>/<student>/<chapter>.ipynb,
#                JOBS at a time, into results.json and feedback.html beside each (tools/grading/grade_many.py);
#                MAX_PROCESSES=n caps each submission's kernel at n processes (default 256; 0: no cap)
#   make gradescope CH=03_three_rpr   the chapter's Gradescope autograder zip, in _build/gradescope/
#                (tools/grading/gradescope.py; the instructor's: it holds the solutions and hidden tests);
#                MAX_PROCESSES=n for its run_autograder (default 0: Gradescope's container is the cap)
#   make chapter NAME=scara TITLE="The SCARA arm" [ROBOT="a SCARA arm"]  a new chapter
#                (tools/authoring/new_chapter.py; book/authoring.md explains it)
#   make bench   print the benchmark tables
#   make clean   remove the built book and caches (keeps .venv)

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# the installer of the venv's packages (pinned: the set-up does not change under us)
UV     := uv==0.13.9
HTML   := _build/html

# EDITION=instructor (default): the book with collapsed solutions, in _build/html.
# EDITION=student: the same pages without solutions, in _build/student/_build/html.
# Neither edition executes a notebook (_config.yml, execute_notebooks: "off"): executing
# them again would compute the outputs `make execute` stored and nbval checks.
EDITION ?= instructor
ifeq ($(EDITION),student)
BOOK_HTML := _build/student/_build/html
BOOK_OPTS := --path-output _build/student
else ifeq ($(EDITION),instructor)
BOOK_HTML := $(HTML)
BOOK_OPTS :=
else
$(error EDITION must be 'instructor' or 'student', not '$(EDITION)')
endif

.PHONY: book student grade test test-all quick lab execute chapter bench clean distclean check-python

# The Python that builds the venv (or, once it exists, the venv's own) must be >= 3.11.
check-python:
	@PY=$(PYTHON); test -x $(BIN)/python && PY=$(BIN)/python; \
	$$PY -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else 1)' 2>/dev/null || { \
	  echo "ERROR [set-up]: robokin needs Python >= 3.11, but '$$PY' is $$($$PY --version 2>&1 || echo 'not found')."; \
	  echo "Fix: install Python 3.11 or newer and run e.g. 'make PYTHON=python3.11 $(MAKECMDGOALS)'"; \
	  echo "     (remove .venv first if it was made with an older Python)."; exit 1; }

# The virtual environment is (re)built when requirements or the package metadata change.
$(STAMP): requirements.txt constraints.txt pyproject.toml | check-python
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV) || { \
	  echo "ERROR [set-up]: could not create the virtual environment $(VENV)."; \
	  echo "Fix: on Debian/Ubuntu install the venv module: 'apt-get install python3-venv'."; exit 1; }
	@echo "== Installing the workbook's Python packages into $(VENV) (first time: about half a minute) =="
	@# uv installs the same pinned set as pip (requirements.txt + constraints.txt) in about a
	@# fifth of the time (33 s against 157 s from an empty cache on the 2-core machine).
	@$(BIN)/python -m pip install --quiet $(UV) && \
	  $(BIN)/python -m uv pip install --quiet --python $(BIN)/python -r requirements.txt || { \
	  echo "ERROR [set-up]: 'uv pip install -r requirements.txt' failed (see the messages above)."; \
	  echo "Fix: check your network connection to PyPI, then run the command again."; exit 1; }
	@touch $(STAMP)

# --all: Sphinx reads every page again (about 30 CPU-s an edition instead of 15 when few pages
# changed): an incremental build does not read a page that did not change, so it would not
# repeat that page's warning and -W would pass a book that has one (tests/conftest.py builds
# the same way).
book: $(STAMP)
	@echo "== Building the $(EDITION) edition of the book from the notebooks' stored outputs (make execute computes them) =="
	@rm -f $(BOOK_HTML)/.complete
	@ROBOKIN_EDITION=$(EDITION) $(BIN)/jupyter-book build . --all -W -n --keep-going $(BOOK_OPTS) || { \
	  rm -rf $(BOOK_HTML); \
	  echo "ERROR [book]: the build failed; $(BOOK_HTML) was removed so that no half-built book is left."; \
	  echo "Fix: read the first error above (a broken reference or citation, a warning)."; exit 1; }
	@touch $(BOOK_HTML)/.complete
	@echo ""
	@echo "The book ($(EDITION) edition) is ready. Open this file in your browser:"
	@echo "    file://$(CURDIR)/$(BOOK_HTML)/index.html"

# The student edition of every chapter, made by nbgrader from the chapter notebooks
# and their nbgrader metadata (tools/authoring/nbgrader_metadata.py); see book/for-instructors.md.
student: $(STAMP)
	@echo "== Making the nbgrader course and the student edition of every chapter =="
	@$(BIN)/python tools/authoring/student_edition.py || { \
	  echo "ERROR [student]: see the messages above."; exit 1; }

# Grade every submission of a chapter in a folder of <student>/<chapter>.ipynb, JOBS at a time
# (default: the number of cores), each into <student>/results.json (Gradescope's format) and
# feedback.html (tools/grading/grade_many.py; one notebook: tools/grading/grade_submission.py).
grade: $(STAMP)
	@test -n "$(CH)" -a -n "$(SUBMISSIONS)" || { echo 'usage: make grade CH=03_three_rpr SUBMISSIONS=folder [JOBS=2] [MAX_PROCESSES=256]'; exit 2; }
	@$(BIN)/python tools/grading/grade_many.py "$(CH)" "$(SUBMISSIONS)" $(if $(JOBS),--jobs $(JOBS)) \
	  $(if $(MAX_PROCESSES),--max-processes $(MAX_PROCESSES))

# Two pytest-xdist workers by default (tests/support/parallel_plan.py); `make test PYTEST_ARGS=-n0`
# runs everything in one process.
PYTEST_ARGS ?=
# make test: three workers (244 s instead of 296 s with two, the ten chapters in, 2-core machine:
# its graded chapter waits for its kernels and time limits while the other workers compute).
TEST_WORKERS ?= 3
# make test-all: four workers on the two cores. Its grading jobs spend about half their time
# waiting (hangs and time limits reached on purpose, kernels starting): with two workers one core
# was idle on average (benchmarks/README.md, "The test suite"); four overlap one job's waits with
# another's work. Every time limit in the suite is a ceiling such a load does not reach.
TEST_ALL_WORKERS ?= 4

# The tests write Python's bytecode caches (__pycache__, git-ignored; `make clean` removes
# them) even where the environment sets PYTHONDONTWRITEBYTECODE, as many containers and CI
# images do: a run starts some 300 Python processes (notebook and grading kernels, nbgrader
# commands, pytest workers), and without the caches every one of them compiles robokin,
# tools/ and the rewritten test modules again (collection alone: 5.6 instead of 3.4 s of CPU).
test test-all quick execute: export PYTHONDONTWRITEBYTECODE :=
test: $(STAMP)
	@$(BIN)/python -m pytest -n $(TEST_WORKERS) -m "not exhaustive" $(PYTEST_ARGS) || { \
	  echo "ERROR [test]: some tests failed (see the summary above)."; exit 1; }

test-all: $(STAMP)
	@$(BIN)/python -m pytest -n $(TEST_ALL_WORKERS) $(PYTEST_ARGS) || { \
	  echo "ERROR [test-all]: some tests failed (see the summary above)."; exit 1; }

QUICK := not notebooks and not book and not browser and not nbgrader and not other_machines
quick: $(STAMP)
	@$(BIN)/python -m pytest tests -q -m "$(QUICK)" $(PYTEST_ARGS) || { \
	  echo "ERROR [quick]: some tests failed (see above); make test runs everything."; exit 1; }

lab: $(STAMP)
	ROBOKIN_VIEWER=live $(BIN)/jupyter lab notebooks/

NB ?= notebooks/[0-9]*.ipynb
execute: $(STAMP)
	@for nb in $(NB); do \
	  test -f "$$nb" || { echo "ERROR [execute]: no notebook $$nb (NB= takes paths such as notebooks/02_ur10_ik.ipynb)"; exit 1; }; \
	  echo "== executing $$nb"; \
	  ROBOKIN_VIEWER=static $(BIN)/jupyter nbconvert --to notebook --execute --inplace \
	    --ExecutePreprocessor.timeout=300 --ExecutePreprocessor.record_timing=False \
	    --ExecutePreprocessor.kernel_manager_class=tools.kernel_sockets.AsyncPrivateSocketsKernelManager "$$nb" || exit 1; \
	  $(BIN)/jupyter nbconvert --to notebook --inplace --log-level=WARN \
	    --CoalesceStreamsPreprocessor.enabled=True "$$nb" || exit 1; \
	done

chapter: $(STAMP)
	@test -n "$(NAME)" -a -n "$(TITLE)" || { echo 'usage: make chapter NAME=scara TITLE="The SCARA arm" [ROBOT="a SCARA arm"]'; exit 1; }
	@$(BIN)/python tools/authoring/new_chapter.py --name "$(NAME)" --title "$(TITLE)" $(if $(ROBOT),--robot "$(ROBOT)")

bench: $(STAMP)
	@for script in benchmarks/bench_*.py; do echo "== $$script"; $(BIN)/python "$$script" || exit 1; done

clean:
	rm -rf _build .pytest_cache .hypothesis
	find robokin tools tests book notebooks -name __pycache__ -type d -prune -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV)

# One chapter's tests, with only that chapter graded: make test-chapter CH=03_three_rpr
# (its notebook under nbval, its notebook conventions, the tests of its check modules
# (tests/test_check_<module>.py), its grading mutations, the contracts of its student
# edition, its hidden tests kept out of the student book, nbgrader, the trust suite and the
# delegation check; every tier).
.PHONY: test-chapter
test-chapter: $(STAMP)
	@test -n "$(CH)" -a -f "notebooks/$(CH).ipynb" || { \
	  echo "ERROR [test-chapter]: CH= names a chapter notebook, e.g. 'make test-chapter CH=03_three_rpr' (got '$(CH)')."; exit 1; }
	@ALONE=$$(mktemp -d) && mkdir "$$ALONE/notebooks" && cp "notebooks/$(CH).ipynb" "$$ALONE/notebooks/" && \
	CHECKS=$$($(BIN)/python -c 'import json, sys; nb = json.load(open(sys.argv[1])); \
	  print(" ".join(sorted({"test_check_" + check.split(".")[0] for cell in nb["cells"] \
	  for check, _ in cell.get("metadata", {}).get("robokin", {}).get("explain", [])})))' "notebooks/$(CH).ipynb") && \
	FILES=$$(for name in $$CHECKS; do if test -f "tests/$$name.py"; then echo "tests/$$name.py"; fi; done) && \
	KEYS=$$(for name in $$CHECKS; do if test -f "tests/$$name.py"; then printf ' or %s' "$$name"; fi; done) && \
	ROBOKIN_NBGRADER_NOTEBOOKS="$$ALONE/notebooks" $(BIN)/python -m pytest $(PYTEST_ARGS) "notebooks/$(CH).ipynb" \
	  tests/test_notebook_conventions.py $$FILES tests/test_grading_mutations.py tests/test_student_edition_contracts.py \
	  tests/test_hidden_tests.py tests/test_nbgrader.py tests/test_grading_trust.py tests/test_grading_tamper.py \
	  -k "$(CH)$$KEYS"; \
	status=$$?; rm -rf "$$ALONE"; test $$status -eq 0 || { \
	  echo "ERROR [test-chapter]: some tests of $(CH) failed (see the summary above)."; exit 1; }

# A Gradescope autograder for one chapter: make gradescope CH=03_three_rpr writes
# _build/gradescope/<chapter>.zip (setup.sh, run_autograder, the grading files; tools/grading/gradescope.py).
# It holds the chapter's solutions and hidden tests: the instructor's, never given to students.
.PHONY: gradescope
gradescope: $(STAMP)
	@test -n "$(CH)" || { echo 'usage: make gradescope CH=03_three_rpr [MAX_PROCESSES=0]'; exit 2; }
	@$(BIN)/python tools/grading/gradescope.py "$(CH)" $(if $(MAX_PROCESSES),--max-processes $(MAX_PROCESSES))
