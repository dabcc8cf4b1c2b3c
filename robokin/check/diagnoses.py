r"""Typical mistakes, written as transformations of the reference.

Each diagnosis is a :class:`~robokin.check._core.Diagnosis`: a code and a
function yielding :class:`~robokin.check._core.Mistake` objects -- a transform
``reference -> mistaken reference`` and a message for the student. A check
evaluates each mistaken reference at its sample inputs; the first one that
reproduces the student's answer explains it.

:func:`standard` returns the usual list for a kind of answer. Chapter modules
add their own with :func:`robokin.check.mistake` / :func:`robokin.check.alternatives`
(e.g. a rotation about the wrong axis, a product in the wrong order).

Diagnosis codes
---------------
``transpose``, ``inverse``, ``rotation_block_transposed``, ``transform_transposed``,
``translation_rotated``, ``translation_sign``, ``sign``, ``sign_column``,
``sign_row``, ``sign_entry``, ``degrees_input``, ``degrees_evaluated``,
``degrees_output``, ``negated_variable``, ``swapped_variables``, ``scale``,
``offset`` -- plus, from the checks themselves, ``wrong_axis``,
``composition_order`` and other chapter-specific codes. The check itself reports
``shape``, ``mismatch``, ``constant``, ``symbols`` and ``error``.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from robokin.check._core import Context, Diagnosis, Mistake, RefFn, alternatives, fmt, mistake
from robokin.transforms import transform

__all__ = [
    "transpose",
    "inverse_transform",
    "transform_mistakes",
    "sign_flips",
    "degrees",
    "degrees_output",
    "negated_variable",
    "swapped_variables",
    "scale",
    "offset",
    "composition_order",
    "missing_factor",
    "standard",
]

_XYZ = "xyz"


def _transposed(a: np.ndarray) -> np.ndarray:
    return np.swapaxes(np.asarray(a), -1, -2)


def transpose(kind: str = "matrix") -> Diagnosis:
    """The transpose of the reference (square or not).

    Parameters
    ----------
    kind : str, optional
        ``"rotation"`` and ``"jacobian"`` get their own explanation; others a
        generic one.

    Returns
    -------
    Diagnosis
    """
    messages = {
        "rotation": (
            "{name} is transposed: your matrix is {name}ᵀ = {name}⁻¹, the rotation the other "
            "way round (the signs of the sin terms are swapped). The columns of {name} are the "
            "axes of the second frame written in the first frame."
        ),
        "jacobian": (
            "{name} is transposed: a Jacobian has one row per coordinate of the point and one "
            "column per joint (column j = ∂r/∂q_j)."
        ),
    }
    msg = messages.get(kind, "{name} is transposed: its rows and columns are swapped.")
    return mistake("transpose", lambda ref: (lambda x: _transposed(ref(x))), msg)


def inverse_transform() -> Diagnosis:
    """The inverse of a homogeneous transform (``T_BA`` for ``T_AB``).

    Returns
    -------
    Diagnosis
    """
    return mistake(
        "inverse",
        lambda ref: (lambda x: np.linalg.inv(ref(x))),
        "{name} is inverted: you gave the transform in the opposite direction, {name}⁻¹. "
        "T_AB holds the axes and the origin of frame B written in frame A "
        "(rotation block R_AB, last column the origin of B in A).",
    )


def _homogeneous(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """[[R, p], [0, 1]] for a mistaken rotation block R (not checked: it may not be a rotation)."""
    return transform(R, p, check=False)


def transform_mistakes() -> list[Diagnosis]:
    """Mistakes inside a homogeneous transform ``[[R, p], [0, 1]]``.

    Returns
    -------
    list of Diagnosis
    """
    return [
        mistake(
            "rotation_block_transposed",
            lambda ref: (lambda x: _homogeneous(ref(x)[:3, :3].T, ref(x)[:3, 3])),
            "the rotation block of {name} is transposed (Rᵀ instead of R, the rotation the "
            "other way round); its translation column is right.",
        ),
        mistake(
            "transform_transposed",
            lambda ref: (lambda x: ref(x).T),
            "{name} is transposed: the translation belongs in the last column and the last "
            "row must be [0, 0, 0, 1].",
        ),
        mistake(
            "translation_rotated",
            lambda ref: (lambda x: _homogeneous(ref(x)[:3, :3], ref(x)[:3, :3] @ ref(x)[:3, 3])),
            "the translation column of {name} is multiplied by the rotation (R·p). The "
            "translation is the origin of the second frame written in the first frame; the "
            "joint rotation turns what comes after it, not this offset.",
        ),
        mistake(
            "translation_rotated",
            lambda ref: (lambda x: _homogeneous(ref(x)[:3, :3], ref(x)[:3, :3].T @ ref(x)[:3, 3])),
            "the translation column of {name} is multiplied by Rᵀ. The translation is the "
            "origin of the second frame written in the first frame, with no rotation applied.",
        ),
        mistake(
            "translation_sign",
            lambda ref: (lambda x: _homogeneous(ref(x)[:3, :3], -ref(x)[:3, 3])),
            "the translation column of {name} has the wrong sign: it is the vector from the "
            "origin of the first frame to the origin of the second.",
        ),
    ]


def sign_flips(kind: str = "matrix") -> Diagnosis:
    """The whole answer, one column, one row or one entry with the opposite sign.

    Parameters
    ----------
    kind : str, optional
        The kind of answer (see :func:`standard`); ``"jacobian"`` names the joint
        of a wrong column.

    Returns
    -------
    Diagnosis
    """

    def variants(ctx: Context) -> Iterator[Mistake]:
        shape = ctx.R.shape[1:]
        nonzero = np.any(np.abs(ctx.R) > 1e-9, axis=0)
        yield Mistake(
            "sign", lambda ref: (lambda x: -np.asarray(ref(x))),
            "{name} has the wrong sign everywhere: your answer is −{name}.",
        )
        if len(shape) == 1:
            for i in range(shape[0]):
                if not nonzero[i]:
                    continue
                label = f"{_XYZ[i]} component" if shape[0] == 3 else f"component {i + 1}"
                yield Mistake(
                    "sign_entry", _flip((i,)), f"the {label} of {{name}} has the wrong sign."
                )
            return
        if len(shape) != 2:
            return
        rows, cols = shape
        names = [v.label for v in ctx.check.variables]
        for j in range(cols):
            if nonzero[:, j].sum() < 2:  # one non-zero entry: reported as that entry
                continue
            extra = f" (∂/∂{names[j]})" if kind == "jacobian" and cols == len(names) else ""
            yield Mistake(
                "sign_column", _flip((slice(None), j)),
                f"column {j + 1}{extra} of {{name}} has the wrong sign.",
            )
        for i in range(rows):
            if nonzero[i].sum() < 2:
                continue
            yield Mistake(
                "sign_row", _flip((i, slice(None))), f"row {i + 1} of {{name}} has the wrong sign."
            )
        for i in range(rows):
            for j in range(cols):
                if nonzero[i, j]:
                    yield Mistake(
                        "sign_entry", _flip((i, j)),
                        f"entry ({i + 1}, {j + 1}) of {{name}} has the wrong sign.",
                    )

    return Diagnosis("sign", variants)


def _flip(index: tuple) -> Callable[[RefFn], RefFn]:
    """The mistake "the entries at ``index`` have the wrong sign", as a transform of the reference."""

    def transform(ref: RefFn) -> RefFn:
        def f(x: np.ndarray) -> np.ndarray:
            a = np.array(ref(x), dtype=float)
            a[index] = -a[index]
            return a

        return f

    return transform


def _convert_angles(ctx: Context, factor: float):
    mask = np.array([v.kind == "angle" for v in ctx.check.variables], dtype=bool)

    def transform(ref):
        return lambda x: ref(np.where(mask, np.asarray(x) * factor, x))

    return transform, mask


def degrees() -> Diagnosis:
    """Degrees where radians are expected, in either direction (inputs of kind ``"angle"``).

    Returns
    -------
    Diagnosis
    """

    def variants(ctx: Context) -> Iterator[Mistake]:
        to_rad, mask = _convert_angles(ctx, np.pi / 180)
        to_deg, _ = _convert_angles(ctx, 180 / np.pi)
        if not mask.any():
            return
        if ctx.form == "constant":
            yield Mistake(
                "degrees_evaluated", to_deg,
                "{name} was evaluated with the angles in degrees where radians are needed "
                "(e.g. sin(60) instead of sin(60°)). Convert first: np.deg2rad(...).",
            )
            return
        yield Mistake(
            "degrees_input", to_rad,
            "{name} treats its angles as degrees: it equals the reference at angle·π/180. "
            "robokin, numpy and sympy work in radians: use the angles as they come and convert "
            "only numbers you type in degrees, with np.deg2rad.",
        )
        yield Mistake(
            "degrees_evaluated", to_deg,
            "{name} converts its angles to degrees before taking sin/cos (angle·180/π), but "
            "sin and cos expect radians: drop the conversion.",
        )

    return Diagnosis("degrees", variants)


def degrees_output() -> Diagnosis:
    """An angle-valued answer given in degrees (or deg/s).

    Returns
    -------
    Diagnosis
    """
    return mistake(
        "degrees_output",
        lambda ref: (lambda x: np.rad2deg(ref(x))),
        "{name} is in degrees (or deg/s): it is 180/π times the expected value. robokin "
        "works in radians: convert with np.deg2rad.",
    )


def negated_variable() -> Diagnosis:
    """One input with the opposite sign (a joint turning the other way).

    Returns
    -------
    Diagnosis
    """

    def variants(ctx: Context) -> Iterator[Mistake]:
        for i, v in enumerate(ctx.check.variables):
            sign = np.ones(len(ctx.check.variables))
            sign[i] = -1.0
            yield Mistake(
                "negated_variable",
                (lambda s: lambda ref: (lambda x: ref(np.asarray(x) * s)))(sign),
                f"the sign of {v.label} is flipped: your answer is {{name}} with −{v.label} in "
                f"place of {v.label} (a rotation the other way round).",
            )

    return Diagnosis("negated_variable", variants)


def swapped_variables() -> Diagnosis:
    """Two inputs exchanged.

    Returns
    -------
    Diagnosis
    """

    def variants(ctx: Context) -> Iterator[Mistake]:
        vs = ctx.check.variables
        for i in range(len(vs)):
            for j in range(i + 1, len(vs)):
                if vs[i].kind != vs[j].kind:
                    continue
                perm = np.arange(len(vs))
                perm[[i, j]] = perm[[j, i]]
                yield Mistake(
                    "swapped_variables",
                    (lambda p: lambda ref: (lambda x: ref(np.asarray(x)[p])))(perm),
                    f"{vs[i].label} and {vs[j].label} are swapped in {{name}}.",
                )

    return Diagnosis("swapped_variables", variants)


def scale() -> Diagnosis:
    """The answer is a constant multiple of the reference.

    Returns
    -------
    Diagnosis
    """

    def variants(ctx: Context) -> Iterator[Mistake]:
        if ctx.S.shape != ctx.R.shape:
            return
        rr = float(np.sum(ctx.R * ctx.R))
        if rr < 1e-12:
            return
        k = float(np.sum(ctx.S * ctx.R)) / rr
        if abs(k) < 1e-9 or abs(k - 1) < 1e-6 or abs(k + 1) < 1e-6:
            return
        yield Mistake(
            "scale", lambda ref: (lambda x: k * np.asarray(ref(x))),
            f"{{name}} is {fmt(k)} times the expected answer: a factor is wrong "
            "(a length, a gain, a missing or extra constant factor?).",
        )

    return Diagnosis("scale", variants)


def offset() -> Diagnosis:
    """The answer differs from the reference by the same constant at every input.

    Returns
    -------
    Diagnosis
    """

    def variants(ctx: Context) -> Iterator[Mistake]:
        if ctx.S.shape != ctx.R.shape or len(ctx.X) < 2:
            return
        c = np.mean(ctx.S - ctx.R, axis=0)
        if np.max(np.abs(c)) < 1e-9:
            return
        yield Mistake(
            "offset", lambda ref: (lambda x: np.asarray(ref(x)) + c),
            f"{{name}} differs from the expected answer by the same constant {fmt(c)} at "
            "every input: a constant term is missing or extra (a fixed offset between two "
            "frames?).",
        )

    return Diagnosis("offset", variants)


def _product(matrices: list[np.ndarray]) -> np.ndarray:
    out = matrices[0]
    for m in matrices[1:]:
        out = out @ m
    return out


def composition_order(factors: Sequence[tuple[str, Callable]], product_name: str) -> Diagnosis:
    """A product of matrices with its factors in any other order (A·B for B·A, ...).

    ``factors`` are ``[(name, fn), ...]`` in the correct order, each ``fn`` a
    function of the check's inputs; ``product_name`` is the product's name in
    the message (e.g. ``"H_BF"``). All ``k! - 1`` other orders are tried.

    Parameters
    ----------
    factors : sequence of (str, callable)
        Name and function of each factor (inputs (nvars,) to a matrix), in the correct order.
    product_name : str
        The product's name in the message.

    Returns
    -------
    Diagnosis
    """
    names = [n for n, _ in factors]
    right = "·".join(names)
    items = []
    for perm in itertools.permutations(range(len(factors))):
        if list(perm) == list(range(len(factors))):
            continue
        fns = [factors[i][1] for i in perm]
        order = "·".join(names[i] for i in perm)
        items.append((
            (lambda fs: lambda x: _product([f(x) for f in fs]))(fns),
            f"{{name}} multiplies the factors in the wrong order ({order}). Chain them by matching "
            f"inner indices: {product_name} = {right}.",
        ))
    return alternatives("composition_order", items)


def missing_factor(factors: Sequence[tuple[str, Callable]], product_name: str) -> Diagnosis:
    """A product with one of its factors left out.

    Parameters
    ----------
    factors : sequence of (str, callable)
        Name and function of each factor (inputs (nvars,) to a matrix), in the correct order.
    product_name : str
        The product's name in the message.

    Returns
    -------
    Diagnosis
    """
    names = [n for n, _ in factors]
    right = "·".join(names)
    items = []
    for skip in range(len(factors)):
        fns = [f for k, (_, f) in enumerate(factors) if k != skip]
        items.append((
            (lambda fs: lambda x: _product([f(x) for f in fs]))(fns),
            f"{{name}} leaves out the factor {names[skip]}: {product_name} = {right}.",
        ))
    return alternatives("missing_factor", items)


def standard(kind: str = "matrix") -> list[Diagnosis]:
    """The usual diagnoses for a kind of answer.

    Parameters
    ----------
    kind : {"matrix", "rotation", "transform", "vector", "jacobian", "angles"}, optional
        The kind of answer.

    Returns
    -------
    list of Diagnosis
        Tried in order; the first that explains the answer is reported.

    Raises
    ------
    ValueError
        An unknown ``kind``.
    """
    common = [degrees(), negated_variable(), swapped_variables()]
    if kind == "rotation":
        return [transpose("rotation"), sign_flips(kind), *common, scale()]
    if kind == "transform":
        return [inverse_transform(), *transform_mistakes(), sign_flips(kind), *common, offset()]
    if kind == "vector":
        return [sign_flips(kind), *common, offset(), scale()]
    if kind == "jacobian":
        return [transpose("jacobian"), sign_flips(kind), *common, scale()]
    if kind == "angles":
        return [degrees_output(), sign_flips(kind), *common, scale(), offset()]
    if kind == "matrix":
        return [transpose(), sign_flips(kind), *common, scale(), offset()]
    raise ValueError(
        f"kind must be one of 'matrix', 'rotation', 'transform', 'vector', 'jacobian', "
        f"'angles'; got {kind!r}"
    )
