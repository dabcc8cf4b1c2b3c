"""Submissions that tamper with the grading: each kind of tampering, put at the top of the first
answer cell (tests/test_grading_tamper.py grades them; tests/test_grading_engines.py hands one
to every grading engine). Each must score exactly what its untampered answers score."""

from __future__ import annotations

import copy

from support.nbgrader_course import nbg, src

#: code put at the top of the first answer cell, by kind of tampering
TAMPER = {
    "input_transformer": (
        "get_ipython().input_transformers_post.append("
        "lambda lines: ['pass\\n'] if 'assert' in ''.join(lines) else lines)\n"),
    "ast_transformer": (
        "import ast as _ast\n"
        "class _NoAsserts(_ast.NodeTransformer):\n"
        "    def visit_Assert(self, node):\n"
        "        return _ast.Pass()\n"
        "get_ipython().ast_transformers.append(_NoAsserts())\n"),
    "display_hook": (
        "import sys as _sys\n"
        "get_ipython().events.register('pre_run_cell', lambda info: _sys.displayhook('full marks'))\n"),
    "patched_numpy": (
        "import numpy as _np\n"
        "_np.allclose = lambda *a, **k: True\n"
        "_np.isclose = lambda *a, **k: _np.True_\n"),
    "forged_check": (
        "import json as _json, sys as _sys\n"
        "import robokin.check.grading as _grading, robokin.check._core as _core\n"
        "def _all_correct(namespace, pairs, marker='ROBOKIN-VERDICTS'):\n"
        "    data = [{'check': c, 'quantity': q, 'status': 'correct', 'diagnosis': None,\n"
        "             'typical': False, 'message': 'correct'} for c, q in pairs]\n"
        "    _sys.stdout.write(marker + ' ' + _json.dumps(data) + '\\n')\n"
        "_grading.print_verdicts = _all_correct\n"
        "_grading.require = lambda *a, **k: None\n"
        "_core.CheckResult.passed = property(lambda self: True)\n"),
    "forged_outputs": (
        "get_ipython().showtraceback = lambda *a, **k: None\n"
        "get_ipython().showsyntaxerror = lambda *a, **k: None\n"
        "get_ipython().events.register('post_run_cell', lambda result: setattr(result, 'error_in_exec', None))\n"),
}


def _first_answer(nb: dict) -> dict:
    return next(c for c in nb["cells"] if nbg(c).get("solution"))


def tampered(base: dict, kind: str) -> dict:
    nb = copy.deepcopy(base)
    cell = _first_answer(nb)
    cell["source"] = TAMPER[kind] + src(cell)
    if kind == "forged_outputs":   # test cells handed in with a full-marks result
        for test in (c for c in nb["cells"] if nbg(c).get("grade")):
            test["outputs"] = [{"output_type": "execute_result", "execution_count": 1, "metadata": {},
                                "data": {"text/plain": "1.0"}}]
    return nb
