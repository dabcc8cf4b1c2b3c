"""Tests of the generic exercise-check machinery (robokin.check, robokin.check.diagnoses)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from robokin import check
from robokin.check import CheckResult, Variable, alternatives, matrix_function, mistake, value
from robokin.check._core import FunctionCheck, MatrixArgumentsCheck
from robokin.check.diagnoses import standard

a, b, g = sp.symbols("alpha beta gamma", real=True)


def Rx(t):
    return sp.Matrix([[1, 0, 0], [0, sp.cos(t), -sp.sin(t)], [0, sp.sin(t), sp.cos(t)]])


def Ry(t):
    return sp.Matrix([[sp.cos(t), 0, sp.sin(t)], [0, 1, 0], [-sp.sin(t), 0, sp.cos(t)]])


def H(R, p):
    M = sp.eye(4)
    M[:3, :3] = R
    M[:3, 3] = sp.Matrix(p)
    return M


def rx_np(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot(student, **kw):
    return matrix_function(student, Rx(a), [a], name="R", kind="rotation", quiet=True, **kw)


# ---------------------------------------------------------------- correct answers
@pytest.mark.parametrize(
    "answer",
    [
        Rx(a),
        Rx(sp.Symbol("alpha")),  # other assumptions: matched by name
        Rx(sp.Symbol("theta")),  # a single unknown symbol for a single variable
        rx_np,  # a function of the angle
        lambda alpha: Rx(alpha),  # a function returning a sympy Matrix
        sp.ImmutableMatrix(Rx(a)),
        [[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]],  # nested list
    ],
)
def test_correct_forms_pass(answer):
    r = rot(answer)
    assert r.passed and r.diagnosis is None and bool(r)
    assert r.message == "✔ R is correct (checked at 20 random angles)."
    assert r.samples == 20


def test_pass_prints_one_line(capsys):
    r = matrix_function(Rx(a), Rx(a), [a], name="R_B1", kind="rotation")
    out = capsys.readouterr().out
    assert out == "✔ R_B1 is correct (checked at 20 random angles).\n"
    assert repr(r) == "CheckResult(name='R_B1', passed=True, diagnosis=None)"


def test_vector_function_of_q_called_with_vector_or_scalars():
    ref = sp.Matrix([sp.cos(a) + b, sp.sin(g) * a, 1])
    f_vec = lambda q: np.array([np.cos(q[0]) + q[1], np.sin(q[2]) * q[0], 1.0])  # noqa: E731
    f_sc = lambda x, y, z: [np.cos(x) + y, np.sin(z) * x, 1.0]  # noqa: E731
    for f in (f_vec, f_sc, ref, ref.T):  # (1, 3) row accepted for a vector
        assert matrix_function(f, ref, [a, b, g], kind="vector", quiet=True).passed


def test_symbols_q1_q2_accepted_for_named_variables():
    q1, q2 = sp.symbols("q1 q2")
    v = [Variable("alpha", aliases=("q1",)), Variable("beta", aliases=("q2",))]
    assert matrix_function(sp.sin(q1) * q2, sp.sin(a) * b, v, quiet=True).passed


# ---------------------------------------------------------------- failures do not raise unless asked
def test_wrong_answer_prints_and_does_not_raise(capsys):
    r = matrix_function(Rx(a).T, Rx(a), [a], name="R_B1", kind="rotation")
    out = capsys.readouterr().out
    assert out.startswith("✘ R_B1 is transposed")
    assert not r.passed and r.diagnosis == "transpose" and r.message.split() == out.split()
    assert max(len(line) for line in out.splitlines()) <= 80        # printed wrapped, message unchanged


def test_raise_on_fail():
    with pytest.raises(AssertionError, match="transposed"):
        rot(Rx(a).T, raise_on_fail=True)
    assert rot(Rx(a), raise_on_fail=True).passed


def test_quiet_prints_nothing(capsys):
    rot(Rx(a).T)
    assert capsys.readouterr().out == ""


# ---------------------------------------------------------------- each generic diagnosis fires
def _flip(M, i, j):
    M = M.copy()
    M[i, j] = -M[i, j]
    return M


@pytest.mark.parametrize(
    "answer, code, text",
    [
        (Rx(a).T, "transpose", "R is transposed"),
        (Rx(-a), "transpose", "Rᵀ = R⁻¹"),
        (-Rx(a), "sign", "wrong sign everywhere"),
        (_flip(Rx(a), 1, 2), "sign_entry", "Entry (2, 3) of R has the wrong sign."),
        (Rx(a * sp.pi / 180), "degrees_input", "treats its angles as degrees"),
        (Rx(a * 180 / sp.pi), "degrees_evaluated", "converts its angles to degrees"),
        (2 * Rx(a), "scale", "R is 2 times the expected answer"),
        (Rx(a)[:, :2], "shape", "should be a 3×3 matrix; your answer is a 3×2 matrix"),
        (sp.eye(3) * a, "mismatch", "differ from the reference"),
        (sp.eye(3), "constant", "should depend on α"),
        (Rx(sp.Symbol("x")) * sp.Symbol("y"), "symbols", "contains the symbol(s) x, y"),
    ],
)
def test_rotation_diagnoses(answer, code, text):
    r = rot(answer)
    assert not r.passed
    assert r.diagnosis == code, r.message
    assert text in r.message
    assert r.message.startswith("✘ ")


def test_column_and_row_sign():
    M = sp.Matrix([[a, b, 1], [sp.cos(a), 2, b], [3, sp.sin(b), a * b]])
    col = M.copy()
    col[:, 1] = -col[:, 1]
    row = M.copy()
    row[2, :] = -row[2, :]
    r = matrix_function(col, M, [a, b], name="M", quiet=True)
    assert r.diagnosis == "sign_column" and r.message == "✘ Column 2 of M has the wrong sign."
    r = matrix_function(row, M, [a, b], name="M", quiet=True)
    assert r.diagnosis == "sign_row" and r.message == "✘ Row 3 of M has the wrong sign."


def test_vector_component_sign_uses_xyz():
    v = sp.Matrix([sp.cos(a), sp.sin(a), a])
    w = sp.Matrix([sp.cos(a), -sp.sin(a), a])
    r = matrix_function(w, v, [a], name="r", kind="vector", quiet=True)
    assert r.diagnosis == "sign_entry" and "The y component of r has the wrong sign." in r.message


def test_negated_and_swapped_variables():
    M = sp.Matrix([[sp.cos(a + 2 * b), sp.sin(a)], [b, a * b]])
    r = matrix_function(M.subs(b, -b), M, [a, b], name="M", quiet=True)
    assert r.diagnosis == "negated_variable" and "The sign of β is flipped" in r.message
    r = matrix_function(M.subs({a: b, b: a}, simultaneous=True), M, [a, b], name="M", quiet=True)
    assert r.diagnosis == "swapped_variables" and "α and β are swapped in M" in r.message


def test_offset():
    v = sp.Matrix([sp.cos(a), sp.sin(b), a])
    r = matrix_function(v + sp.Matrix([0, 1, 0]), v, [a, b], name="r", kind="vector", quiet=True)
    assert r.diagnosis == "offset" and "by the same constant [0, 1, 0]" in r.message


def test_degrees_input_for_a_python_function():
    r = rot(lambda alpha_deg: rx_np(np.deg2rad(alpha_deg)))
    assert r.diagnosis == "degrees_input"


def test_degrees_in_a_numeric_answer_at_a_fixed_input():
    ref = lambda x: np.array([np.sin(x[0]), np.cos(x[1])])  # noqa: E731
    chk = check.Check("v", ref, [Variable("alpha"), Variable("beta")], at=[np.pi / 3, 0.5],
                      diagnoses=standard("vector"), atol=1e-3)
    assert chk([np.sin(np.pi / 3), np.cos(0.5)], quiet=True).passed
    r = chk([np.sin(60.0), np.cos(np.rad2deg(0.5))], quiet=True)
    assert r.diagnosis == "degrees_evaluated" and "sin(60) instead of sin(60°)" in r.message


def test_degrees_output_for_angles():
    r = value(np.rad2deg([0.1, -0.2]), [0.1, -0.2], name="q", kind="angles", quiet=True)
    assert r.diagnosis == "degrees_output"
    assert value([0.1004, -0.2], [0.1, -0.2], name="q", kind="angles", quiet=True).passed


@pytest.mark.parametrize(
    "answer, code, text",
    [
        (H(Rx(a), [0, 1, 0]).inv(), "inverse", "H is inverted"),
        (H(Rx(a).T, [0, 1, 0]), "rotation_block_transposed", "rotation block of H is transposed"),
        (H(Rx(a), [0, 1, 0]).T, "transform_transposed", "last row must be [0, 0, 0, 1]"),
        (H(Rx(a), Rx(a) * sp.Matrix([0, 1, 0])), "translation_rotated", "multiplied by the rotation"),
        (H(Rx(a), [0, -1, 0]), "translation_sign", "translation column of H has the wrong sign"),
        (Rx(a), "shape", "A homogeneous transform is 4×4"),
    ],
)
def test_transform_diagnoses(answer, code, text):
    r = matrix_function(answer, H(Rx(a), [0, 1, 0]), [a], name="H", kind="transform", quiet=True)
    assert r.diagnosis == code, r.message
    assert text in r.message


def test_shape_hint_for_block_and_homogeneous_point():
    r = matrix_function(H(Rx(a), [0, 1, 0]), Rx(a), [a], name="R", kind="rotation", quiet=True)
    assert r.diagnosis == "shape" and "top-left 3×3 block is right" in r.message
    p = sp.Matrix([sp.cos(a), 1, 0])
    r = matrix_function(sp.Matrix([sp.cos(a), 1, 0, 1]), p, [a], name="p", kind="vector", quiet=True)
    assert r.diagnosis == "shape" and "first 3 entries are right" in r.message


def test_jacobian_transpose_and_column_names():
    r_ = sp.Matrix([sp.cos(a) * b, sp.sin(a) + b * b, a])
    J = r_.jacobian([a, b])
    res = matrix_function(J.T, J, [a, b], name="J", kind="jacobian", quiet=True)
    assert res.diagnosis == "transpose" and "one column per joint" in res.message
    Jc = J.copy()
    Jc[:, 0] = -Jc[:, 0]
    res = matrix_function(Jc, J, [a, b], name="J", kind="jacobian", quiet=True)
    assert res.message == "✘ Column 1 (∂/∂α) of J has the wrong sign."


# ---------------------------------------------------------------- unusable answers
def test_function_that_raises_is_reported():
    def broken(alpha):
        raise ZeroDivisionError("oops")

    r = rot(broken)
    assert r.diagnosis == "error" and "raised ZeroDivisionError: oops" in r.message


def test_none_and_nan_answers():
    assert rot(None).diagnosis == "error"
    assert "did you forget to return" in rot(None).message
    assert rot(lambda t: np.full((3, 3), np.nan)).diagnosis == "error"


def test_function_without_return_is_told_to_return():
    def forgot(alpha):
        np.cos(alpha)   # computed, never returned

    r = rot(forgot)
    assert r.diagnosis == "error" and "is None: did you forget `return`?" in r.message
    assert "NaN" not in r.message


def test_non_numeric_answer():
    r = value("abc", [1.0], quiet=True)
    assert r.diagnosis == "error" and "not numeric" in r.message


# ---------------------------------------------------------------- extension points
class _Doubles(FunctionCheck):
    """A FunctionCheck of f(x) -> 2 x on three cases, with one named mistake."""

    def judge(self, answer):
        cases = (1.0, 2.0, -3.0)
        got = [self.call(answer, (x,), f"at x = {x}") for x in cases]
        if got == [2 * x for x in cases]:
            return self.success(f"{self.name} is correct.", len(cases))
        named = self.diagnose([("halves", "{name} halves x."), ("same", "{name} returns x.")],
                              lambda code: got == [x / 2 if code == "halves" else x for x in cases],
                              len(cases))
        if named is not None:   # not `named or ...`: a failed CheckResult is falsy
            return named
        return self.failure("mismatch", f"{self.name} is not 2 x.", len(cases))


def test_function_check_refuses_none_and_non_functions_without_judging():
    doubles = _Doubles(name="double", signature="double(x) -> 2 x")
    none, number = doubles(None, quiet=True), doubles(3.0, quiet=True)
    assert (none.diagnosis, none.message, none.samples) == (
        "error", "✘ double is None: did you forget to define it?", 0)
    assert (number.diagnosis, number.message) == (
        "constant", "✘ double should be a Python function double(x) -> 2 x; got float.")
    assert doubles(np.zeros(3), quiet=True).diagnosis == "constant"


def test_function_check_calls_reports_and_names_mistakes():
    doubles = _Doubles(name="double", signature="double(x) -> 2 x")
    assert doubles(lambda x: 2 * x, quiet=True).message == "✔ double is correct."
    assert doubles(lambda x: x / 2, quiet=True).message == "✘ double halves x."
    assert doubles(lambda x: x, quiet=True).diagnosis == "same"
    assert doubles(lambda x: x + 1, quiet=True).diagnosis == "mismatch"

    def broken(x):
        if x < 0:
            raise ValueError("negative")
        return 2 * x

    r = doubles(broken, quiet=True)
    assert (r.diagnosis, r.message, r.samples) == (
        "error", "✘ calling double at x = -3.0 raised ValueError: negative", 1)
    with pytest.raises(NotImplementedError, match="judge"):
        FunctionCheck(name="f").evaluate(abs)


def test_matrix_arguments_check_compares_the_packed_value():
    def pack(out):
        if not isinstance(out, tuple):
            raise TypeError(f"return a pair; got {type(out).__name__}")
        return np.r_[out[0], out[1]]

    check_pair = MatrixArgumentsCheck(
        name="pair(v)", reference=lambda x: np.r_[2 * x, x.sum()], variables=[Variable("a"), Variable("b")],
        arguments=lambda x: (x,), signature="pair(v) -> (2 v, sum)", pack=pack)
    assert check_pair(lambda v: (2 * v, v.sum()), quiet=True).passed
    assert check_pair(lambda v: (v, v.sum()), quiet=True).diagnosis == "mismatch"
    r = check_pair(lambda v: 2 * v, quiet=True)
    assert r.diagnosis == "error" and "raised TypeError: return a pair; got ndarray" in r.message
    assert check_pair([1.0, 2.0], quiet=True).message == (
        "✘ pair(v) should be a Python function pair(v) -> (2 v, sum); got list.")


def test_custom_mistake_and_alternatives():
    ref = sp.Matrix([sp.cos(a), sp.sin(a)])
    half = mistake("half_angle", lambda f: (lambda x: f(np.asarray(x) / 2)),
                   "{name} uses half the angle.")
    r = matrix_function(ref.subs(a, a / 2), ref, [a], name="u", diagnoses=[half], quiet=True)
    assert r.diagnosis == "half_angle" and r.message == "✘ u uses half the angle."
    alt = alternatives("swap_xy", [(lambda x: np.array([np.sin(x[0]), np.cos(x[0])]),
                                    "{name} has x and y swapped.")])
    r = matrix_function(sp.Matrix([sp.sin(a), sp.cos(a)]), ref, [a], name="u",
                        diagnoses=[alt], quiet=True)
    assert r.diagnosis == "swap_xy"


def test_a_mistake_equal_to_the_reference_is_skipped():
    sym = sp.Matrix([[sp.cos(a), sp.sin(a)], [sp.sin(a), 1]])  # symmetric: transpose == itself
    r = matrix_function(sym * 3, sym, [a], name="S", quiet=True)
    assert r.diagnosis == "scale"


def test_samples_are_seeded_and_deterministic():
    c1 = check.Check("x", lambda x: x, [Variable("alpha")], seed=3)
    c2 = check.Check("x", lambda x: x, [Variable("alpha")], seed=3)
    assert np.array_equal(c1.sample_points(), c2.sample_points())
    assert c1.sample_points().shape == (20, 1)
    m1 = rot(sp.eye(3) * a).message
    assert m1 == rot(sp.eye(3) * a).message


def test_value_check_and_tolerance():
    ref = [[0.5, np.sqrt(3) / 2], [1.0, 2.0]]
    assert value([[0.5, 0.866], [1, 2]], ref, quiet=True).passed
    r = value([[0.5, 0.8], [1, 2]], ref, name="x", quiet=True)
    assert r.diagnosis == "mismatch" and "entry (1, 2) should be 0.866, yours is 0.8" in r.message


def test_values_shown_false_names_the_wrong_entries_not_their_values():
    """A check of numbers the statement asks for at one input: its reference there is the answer,
    so a wrong answer no typical mistake explains is told which entries differ and the hint."""
    ref = np.array([[0.5, np.sqrt(3) / 2], [1.0, 2.0]])
    hidden = check.Check("M", lambda x: ref, [], [], standard("matrix"), values_shown=False,
                         hint="Read the statement again.")
    r = hidden([[0.5, 0.8], [1, 2.5]], quiet=True)
    assert r.message == "✘ M is not correct: entries (1, 2), (2, 2) differ. Read the statement again."
    assert "0.866" not in r.message and "should be" not in r.message, r.message
    assert hidden(ref + 0.1, quiet=True).message.startswith("✘ M is not correct: every entry differs.")
    assert hidden(ref, quiet=True).passed and hidden(ref.T, quiet=True).diagnosis == "transpose"
    at_one_input = check.Check("y", lambda x: np.sin(x[0]), [Variable("alpha")], at=[0.3],
                               at_text="α = 0.3", values_shown=False)
    assert at_one_input(0.2, quiet=True).message == "✘ y is not correct at α = 0.3."
    # shown by default: the example value (a test's own reference, random inputs)
    shown = check.Check("y", lambda x: np.sin(x[0]), [Variable("alpha")], at=[0.3], at_text="α = 0.3")
    assert "expected 0.296, got 0.2" in shown(0.2, quiet=True).message


def test_result_is_truthy_and_has_fields():
    r = CheckResult("n", False, "✘ no", "mismatch", 1)
    assert not r and r.name == "n" and r.samples == 1


def test_unknown_chapter_and_kind():
    with pytest.raises(AttributeError, match="chapters with checks: .*leg"):
        check.chapter_that_does_not_exist  # noqa: B018
    with pytest.raises(ValueError, match="kind must be one of"):
        standard("tensor")


def test_check_does_not_import_views_or_matplotlib():
    code = (
        "import sys, robokin.check, robokin.check.leg\n"
        "bad = [m for m in sys.modules if m.startswith(('robokin.views', 'matplotlib', 'meshcat'))]\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_result_displays_nothing_in_a_notebook(capsys):
    r = rot(Rx(a))
    assert r._ipython_display_() is None
    assert capsys.readouterr().out == ""


def test_composition_order_and_missing_factor_for_any_product():
    from robokin.check.diagnoses import composition_order, missing_factor

    A = lambda x: np.array(Rx(x[0]).evalf(), float)  # noqa: E731
    B = lambda x: np.array(Ry(x[1]).evalf(), float)  # noqa: E731
    C = lambda x: np.diag([1.0, 2.0, x[0]])  # noqa: E731
    factors = [("A", A), ("B", B), ("C", C)]
    diags = [composition_order(factors, "P"), missing_factor(factors, "P")]
    ref = Rx(a) * Ry(b) * sp.diag(1, 2, a)
    r = matrix_function(Ry(b) * Rx(a) * sp.diag(1, 2, a), ref, [a, b], name="P",
                        diagnoses=diags, quiet=True)
    assert r.diagnosis == "composition_order"
    assert r.message == ("✘ P multiplies the factors in the wrong order (B·A·C). Chain them by "
                         "matching inner indices: P = A·B·C.")
    r = matrix_function(Rx(a) * Ry(b), ref, [a, b], name="P", diagnoses=diags, quiet=True)
    assert r.diagnosis == "missing_factor" and "leaves out the factor C" in r.message


def test_function_failing_for_some_inputs_is_reported():
    def picky(alpha):
        if alpha > 1.0:
            raise ValueError("too big")
        return rx_np(alpha)

    r = rot(picky)
    assert r.diagnosis == "error" and "raised ValueError: too big" in r.message


def test_function_returning_varying_shapes():
    r = rot(lambda alpha: rx_np(alpha) if alpha > 0 else rx_np(alpha)[:2])
    assert r.diagnosis == "shape" and "different shapes" in r.message


# ---------------------------------------------------------------- properties
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_entries = st.lists(st.integers(-3, 3), min_size=9, max_size=9)


@settings(max_examples=25, deadline=None)
@given(_entries, st.integers(0, 8))
def test_any_single_sign_slip_is_found(entries, k):
    A = sp.Matrix(3, 3, entries)
    M = A * Rx(a)
    i, j = divmod(k, 3)
    if M[i, j] == 0:
        return
    wrong = M.copy()
    wrong[i, j] = -wrong[i, j]
    r = matrix_function(wrong, M, [a], name="M", quiet=True)
    assert not r.passed and r.diagnosis is not None and r.diagnosis.startswith("sign"), r.message


@settings(max_examples=25, deadline=None)
@given(_entries)
def test_correct_answers_always_pass_and_transposes_are_named(entries):
    M = sp.Matrix(3, 3, entries) * Ry(b)
    assert matrix_function(M, M, [b], quiet=True).passed
    Mf = sp.lambdify(b, M, "numpy")
    if not all(np.allclose(Mf(x), Mf(x).T) for x in (0.3, 1.1, -2.0)):
        assert matrix_function(M.T, M, [b], quiet=True).diagnosis == "transpose"


def test_every_registered_chapter_imports_and_has_checks():
    for chapter in check.CHAPTERS:
        checks = check.checks_of(chapter)
        assert checks, chapter
        module = getattr(check, chapter)
        for attr, chk in checks.items():
            assert getattr(module, attr) is chk


def test_a_wrong_number_per_input_is_explained_with_both_values():
    """A check whose answer is one number per input (a duration): the message gives the
    expected and the given number, not entries of an array."""
    # a reference that gives one number per input, which Check accepts (its annotation says array)
    chk = check.Check("T", lambda x: float(2.0 * np.sum(x)), [Variable("alpha")], seed=3)  # type: ignore[arg-type,return-value]
    assert chk(lambda x: float(2.0 * np.sum(x)), quiet=True).passed
    r = chk(lambda x: float(3.0 * np.sum(x)), quiet=True)
    assert not r.passed and "expected" in r.message and "got" in r.message, r.message


def test_pack_joint_rows_flattens_and_refuses_with_the_expected_form():
    from robokin.check._core import pack_joint_rows

    pack = pack_joint_rows("track", 4, 3)
    rows = np.arange(12.0).reshape(4, 3)
    assert np.array_equal(pack(rows), rows.ravel()) and np.array_equal(pack(rows.tolist()), rows.ravel())
    with pytest.raises(TypeError, match=r"^track should return one array of joint angles \(N, 3\), not a tuple "
                                        r"of 2 items$"):
        pack((rows, 1))
    with pytest.raises(TypeError, match=r"^track should return the joint angles at the N = 4 samples of r_des, "
                                        r"shape \(4, 3\); got shape \(3, 3\)$"):
        pack(rows[1:])


def test_packed_variants_are_the_loop_with_its_mistake_packed():
    from robokin.check._core import packed_variants

    def loop(a, b, *, sign=1.0):
        return [sign * a, b]

    variant = packed_variants(loop, lambda x: (x[0], x[1]), np.asarray)
    x = np.array([2.0, 5.0])
    assert np.array_equal(variant()(x), [2.0, 5.0]) and np.array_equal(variant(sign=-1.0)(x), [-2.0, 5.0])


def test_a_checks_repr_names_it_and_shows_no_message():
    """``help(check)`` and a cell that ends with a check show its repr: the name, not the
    messages of its typical mistakes (which hold the answer's formula)."""
    secret = alternatives("swap_xy", [(lambda x: np.array([np.sin(x[0]), np.cos(x[0])]),
                                       "{name} has x and y swapped: use (cos a, sin a).")])
    made = [
        check.Check(name="u", reference=lambda x: x, variables=[Variable("a")], diagnoses=[secret]),
        MatrixArgumentsCheck(name="pair(v)", reference=lambda x: x, variables=[Variable("a")],
                             arguments=lambda x: (x,), signature="pair(v) -> v", diagnoses=[secret]),
        FunctionCheck(name="f", variables=[Variable("a")], diagnoses=[secret]),
        check.SolutionSetCheck(name="heading", variables=[Variable("t")], reference=lambda x: x,
                               diagnoses=[secret]),
    ]
    for item in made:
        assert item.name in repr(item) and "swapped" not in repr(item) and len(repr(item)) < 80, repr(item)


def test_every_chapters_checks_show_only_their_name():
    """Every check object of every chapter's module (those defined as dataclasses of their own
    too) shows its name, and at most its signature, on one short line: not its fields, whose
    typical mistakes' messages hold the answer's formula (a dataclass repr ran to 2,762
    characters)."""
    import importlib
    import pkgutil

    shown = {}
    for module_info in pkgutil.iter_modules(check.__path__):
        if module_info.name.startswith("_"):
            continue
        module = importlib.import_module(f"robokin.check.{module_info.name}")
        for attribute, item in vars(module).items():
            if isinstance(item, check.Check):
                shown[f"{module_info.name}.{attribute}"] = repr(item)
    assert len(shown) > 50, sorted(shown)
    long = {name: text[:200] for name, text in shown.items() if len(text) > 160 or "\n" in text}
    assert not long, long
