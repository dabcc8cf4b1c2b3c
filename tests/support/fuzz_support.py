"""Argument generators and the oracle of the robustness property suite.

Every public function is described by a :class:`Spec`: its arguments (each an
:class:`Arg` that can produce a *valid* value, a valid but *extreme* one --
huge or tiny finite numbers, a rotation perturbed within tolerance -- and
*corrupted* ones: NaN, inf, wrong shapes, None, strings, lists of strings,
non-orthonormal or reflected rotations, ...) and the shape of its result.

The oracle (:func:`run_example`) draws one example -- at most one corrupted
argument, possibly some extreme ones, a batch size (none, 0, 1 or 3) -- calls
the function and decides:

- all arguments valid and none extreme: the call must return, and the result
  must be finite and of the documented shape;
- one argument corrupted: the call must raise a robokin error, ``ValueError``
  or ``TypeError`` whose message names that argument (for a *student answer*
  of an exercise check: it must return a failed ``CheckResult`` instead);
- extreme arguments: either a finite result of the documented shape, or such
  an error naming one of the extreme arguments.

numpy ``RuntimeWarning`` s (overflow, invalid value) raised during a call are
failures too: a student should never see them.
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from robokin.errors import RobokinError, RobokinWarning

#: Corruptions that apply to every numeric argument.
NONNUMERIC = ("none", "str", "strlist", "object")
NONFINITE = ("nan", "inf", "-inf")
#: Huge and tiny finite values used by ``extreme``.
EXTREMES = (1e300, -1e300, 1.7e308, -1.7e308, 1e154, 1e-300, -5e-324, 1e-12)


class Ctx:
    """Per-example context: batch size, random generator, shared objects (a chain, ...)."""

    def __init__(self, N: int | None, rng: np.random.Generator) -> None:
        self.N = N
        self.rng = rng
        self.extra: dict[str, Any] = {}

    def __getattr__(self, name: str) -> Any:
        try:
            return self.__dict__["extra"][name]
        except KeyError:
            raise AttributeError(name) from None


def _rodrigues(w: np.ndarray) -> np.ndarray:
    """Rotation matrices of rotation vectors (..., 3) -- independent of robokin."""
    w = np.asarray(w, dtype=float)
    th = np.linalg.norm(w, axis=-1)[..., None, None]
    h = w / np.where(th[..., 0] > 0, th[..., 0], 1.0)
    K = np.zeros(w.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -h[..., 2], h[..., 1], -h[..., 0]
    K = K - np.swapaxes(K, -1, -2)
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * (K @ K)


class Arg:
    """One argument: ``valid``, ``extreme`` and ``corrupt`` values.

    Parameters
    ----------
    name : str
        The argument's name as it must appear in error messages.
    labels : sequence of str, optional
        Other accepted spellings in messages (``Ts[0]`` for ``*Ts``).
    bad : sequence of str, optional
        The corruption kinds that must be rejected.
    """

    def __init__(self, name: str, labels: Sequence[str] = (), bad: Sequence[str] | None = None,
                 extreme: bool = True, extra_bad: dict[str, Callable[[Ctx], Any]] | None = None,
                 optional: bool = False) -> None:
        self.optional = optional  # None is a valid value (the default): not a corruption
        self.name = name
        self.labels = (name, *labels)
        self._bad = tuple(bad) if bad is not None else None
        self.has_extreme = extreme
        self.extra_bad = dict(extra_bad or {})

    # -- to override
    def valid(self, ctx: Ctx) -> Any:
        raise NotImplementedError

    def extreme(self, ctx: Ctx) -> Any:
        return self.valid(ctx)

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return NONNUMERIC + NONFINITE

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        return generic_corruption(kind, self.valid(ctx))

    # -- used by the oracle
    def bad_kinds(self, ctx: Ctx) -> tuple[str, ...]:
        base = self._bad if self._bad is not None else self.default_bad(ctx)
        if self.optional:
            base = tuple(k for k in base if k != "none")
        return tuple(base) + tuple(self.extra_bad)

    def make_bad(self, kind: str, ctx: Ctx) -> Any:
        if kind in self.extra_bad:
            return self.extra_bad[kind](ctx)
        return self.corrupt(kind, ctx)

    def named_in(self, message: str) -> bool:
        return any(re.search(rf"(?<![A-Za-z0-9_]){re.escape(lab)}(?![A-Za-z0-9_])", message)
                   for lab in self.labels)


def generic_corruption(kind: str, value: Any) -> Any:
    """Corrupt a valid numeric value (scalar or array)."""
    if kind == "none":
        return None
    if kind == "str":
        return "abc"
    if kind == "strlist":
        n = int(np.size(value)) if np.ndim(value) else 3
        return ["a"] * max(n, 1)
    if kind == "object":
        return object()
    if kind == "complex":
        return np.asarray(value, dtype=float) + 1j
    if kind in NONFINITE:
        bad = {"nan": np.nan, "inf": np.inf, "-inf": -np.inf}[kind]
        a = np.array(value, dtype=float)
        if a.size == 0:
            return bad
        a.flat[a.size // 2] = bad
        return a if a.ndim else float(a)
    raise KeyError(kind)


class Arr(Arg):
    """A float array ``core`` or, when ``batch``, ``(N,) + core``."""

    def __init__(self, name: str, core: tuple[int, ...], *, batch: bool = True, lo: float = -2.0,
                 hi: float = 2.0, sign: int = 0, shape_bad: bool = True, **kw: Any) -> None:
        super().__init__(name, **kw)
        self.core, self.batch, self.lo, self.hi, self.sign = core, batch, lo, hi, sign
        self.shape_bad = shape_bad

    def shape(self, ctx: Ctx) -> tuple[int, ...]:
        return self.core if (not self.batch or ctx.N is None) else (ctx.N, *self.core)

    def valid(self, ctx: Ctx) -> Any:
        a = ctx.rng.uniform(self.lo, self.hi, self.shape(ctx))
        return a if a.ndim else float(a)

    def extreme(self, ctx: Ctx) -> Any:
        a = np.array(self.valid(ctx), dtype=float)
        if a.size == 0:
            return a
        picks = [e for e in EXTREMES if self.sign == 0 or np.sign(e) == self.sign]
        k = int(ctx.rng.integers(1, a.size + 1))
        idx = ctx.rng.choice(a.size, size=k, replace=False)
        a.flat[idx] = ctx.rng.choice(picks, size=k)
        return a if a.ndim else float(a)

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        kinds: tuple[str, ...] = NONNUMERIC + NONFINITE + ("complex",)
        if self.shape_bad:
            kinds += ("shape", "ragged") if self.core else ("shape",)
        return kinds

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "shape":
            shape = self.shape(ctx)
            if self.core:
                choices = [shape[:-1] + (shape[-1] + 1,), (2, 2) + shape]
                if shape[-1] > 1:
                    choices.append(shape[:-1] + (shape[-1] - 1,))
                if len(self.core) > 1:
                    choices.append(self.core[1:])
            else:
                choices = [(2,), (2, 2)]
            pick = choices[int(ctx.rng.integers(len(choices)))]
            return ctx.rng.uniform(self.lo, self.hi, pick)
        if kind == "ragged":
            return [[1.0, 2.0, 3.0], [1.0, 2.0]]
        return generic_corruption(kind, self.valid(ctx))


class Num(Arr):
    """A real scalar, optionally positive (``minimum`` exclusive unless ``allow_zero``)."""

    def __init__(self, name: str, lo: float = 0.1, hi: float = 2.0, *, positive: bool = False,
                 allow_zero: bool = False, **kw: Any) -> None:
        super().__init__(name, (), batch=False, lo=lo, hi=hi, sign=1 if positive else 0, **kw)
        self.positive, self.allow_zero = positive, allow_zero

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        kinds: tuple[str, ...] = NONNUMERIC + NONFINITE + ("complex", "shape")
        if self.positive:
            kinds += ("negative",) + (() if self.allow_zero else ("zero",))
        return kinds

    def extreme(self, ctx: Ctx) -> Any:
        picks = [e for e in EXTREMES if not self.positive or e > 0]
        return float(ctx.rng.choice(picks))

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "negative":
            return -float(ctx.rng.uniform(0.1, 2.0))
        if kind == "zero":
            return 0.0
        return super().corrupt(kind, ctx)


class Int(Arg):
    """An integer in ``[lo, hi]``; ``minimum`` is the smallest accepted value."""

    def __init__(self, name: str, lo: int, hi: int, minimum: int = 0, huge: int | None = None,
                 **kw: Any) -> None:
        kw.setdefault("extreme", huge is not None)
        super().__init__(name, **kw)
        self.lo, self.hi, self.minimum, self.huge = lo, hi, minimum, huge

    def valid(self, ctx: Ctx) -> Any:
        return int(ctx.rng.integers(self.lo, self.hi + 1))

    def extreme(self, ctx: Ctx) -> Any:
        return self.huge

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return ("none", "str", "float", "below", "object")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "float":
            return 1.5
        if kind == "below":
            return self.minimum - 1
        return generic_corruption(kind, 0)


class Choice(Arg):
    """One of a few strings (or other constants)."""

    def __init__(self, name: str, options: Sequence[Any], **kw: Any) -> None:
        kw.setdefault("extreme", False)
        super().__init__(name, **kw)
        self.options = list(options)

    def valid(self, ctx: Ctx) -> Any:
        return self.options[int(ctx.rng.integers(len(self.options)))]

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return ("unknown", "int", "object")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        return {"unknown": "nonsense", "int": 3, "object": object()}[kind]


class Const(Arg):
    """A fixed valid value, never corrupted."""

    def __init__(self, name: str, value: Any) -> None:
        super().__init__(name, bad=(), extreme=False)
        self.value = value

    def valid(self, ctx: Ctx) -> Any:
        return self.value(ctx) if callable(self.value) and not isinstance(self.value, type) else self.value


class Obj(Arg):
    """An object argument (a chain, a controller, a robot): ``make(ctx)`` builds a valid one."""

    def __init__(self, name: str, make: Callable[[Ctx], Any], bad: Sequence[str] = ("none", "str", "int", "list"),
                 **kw: Any) -> None:
        kw.setdefault("extreme", False)
        super().__init__(name, bad=bad, **kw)
        self.make = make

    def valid(self, ctx: Ctx) -> Any:
        return self.make(ctx)

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        return {"none": None, "str": "ur10", "int": 3, "list": [1.0, 2.0], "object": object()}[kind]


class Fn(Obj):
    """A callable argument (a goal function, a feed-forward, ...)."""

    def __init__(self, name: str, make: Callable[[Ctx], Any], **kw: Any) -> None:
        kw.setdefault("bad", ("none", "str", "int"))
        super().__init__(name, make, **kw)


class Limits(Arr):
    """Joint limits (n, 2) with lower <= upper; corruptions add a reversed row."""

    def __init__(self, name: str, n: int, lo: float = -2.0, hi: float = 2.0, **kw: Any) -> None:
        kw.setdefault("extra_bad", {"reversed": lambda ctx: np.tile([1.0, -1.0], (n, 1))})
        kw.setdefault("bad", NONNUMERIC + ("nan", "complex", "shape", "ragged"))  # inf = unlimited: valid
        super().__init__(name, (n, 2), batch=False, lo=lo, hi=hi, **kw)

    def valid(self, ctx: Ctx) -> Any:
        return np.sort(super().valid(ctx), axis=-1)

    def extreme(self, ctx: Ctx) -> Any:
        return np.sort(super().extreme(ctx), axis=-1)


class Rot(Arr):
    """Rotation matrices (3, 3) or (N, 3, 3)."""

    def __init__(self, name: str, batch: bool = True, **kw: Any) -> None:
        super().__init__(name, (3, 3), batch=batch, **kw)

    def valid(self, ctx: Ctx) -> Any:
        return _rodrigues(ctx.rng.uniform(-2, 2, self.shape(ctx)[:-2] + (3,)))

    def extreme(self, ctx: Ctx) -> Any:
        R = self.valid(ctx)
        return R + 1e-9 * ctx.rng.uniform(-1, 1, R.shape)

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return super().default_bad(ctx) + ("nonortho", "reflect")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        R = np.array(self.valid(ctx))
        if R.size == 0:
            R = _rodrigues(np.ones((1, 3)))
        if kind == "nonortho":
            R[..., :, 0] *= 1.5
            return R
        if kind == "reflect":
            R[..., :, 2] *= -1.0
            return R
        return super().corrupt(kind, ctx)


class Tf(Arr):
    """Homogeneous transforms (4, 4) or (N, 4, 4)."""

    def __init__(self, name: str, batch: bool = True, scale: float = 1.0, **kw: Any) -> None:
        super().__init__(name, (4, 4), batch=batch, **kw)
        self.scale = scale

    def valid(self, ctx: Ctx) -> Any:
        lead = self.shape(ctx)[:-2]
        T = np.zeros(lead + (4, 4))
        T[..., :3, :3] = _rodrigues(ctx.rng.uniform(-2, 2, lead + (3,)))
        T[..., :3, 3] = self.scale * ctx.rng.uniform(-1, 1, lead + (3,))
        T[..., 3, 3] = 1.0
        return T

    def extreme(self, ctx: Ctx) -> Any:
        T = self.valid(ctx)
        T[..., :3, 3] = ctx.rng.choice([1e300, -1.7e308, 1e-300], size=T.shape[:-2] + (3,))
        return T

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return super().default_bad(ctx) + ("bottom", "nonortho", "reflect")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        T = np.array(self.valid(ctx))
        if T.size == 0:
            T = np.eye(4)[None]
        if kind == "bottom":
            T[..., 3, :] = [1.0, 0.0, 0.0, 1.0]
            return T
        if kind == "nonortho":
            T[..., :3, 0] *= 1.5
            return T
        if kind == "reflect":
            T[..., :3, 2] *= -1.0
            return T
        return super().corrupt(kind, ctx)


# ---------------------------------------------------------------------- specs
@dataclasses.dataclass
class Spec:
    """How to call one public function and what it must return.

    ``shape(ctx, values)`` gives the expected shape of the result (a tuple, a
    tuple of tuples for a tuple result, or None for no check); ``check(result,
    ctx, values)`` may assert more. ``student`` names arguments that are a
    student's answer to an exercise check: corrupting them must give a failed
    ``CheckResult``, not an exception.
    """

    name: str
    fn: Callable[..., Any]
    args: list[Arg] = dataclasses.field(default_factory=list)
    kwargs: dict[str, Arg] = dataclasses.field(default_factory=dict)
    shape: Callable[[Ctx, dict], Any] | None = None
    check: Callable[[Any, Ctx, dict], object] | None = None
    batch: bool = False
    empty: bool = True
    weight: float = 1.0
    finite: bool = True
    setup: Callable[[Ctx], None] | None = None
    student: tuple[str, ...] = ()
    covers: tuple[str, ...] = ()
    sizes: tuple[int | None, ...] | None = None  # batch sizes to draw (default None, 1, 3 and 0)

    def all_args(self) -> list[tuple[str | int, Arg]]:
        return [(i, a) for i, a in enumerate(self.args)] + list(self.kwargs.items())


def _numeric_leaves(x: Any, path: str = "result", depth: int = 0):
    """Yield (path, array) for every numeric array/number inside a result."""
    if depth > 4 or x is None or isinstance(x, (str, bytes, bool, np.bool_)):
        return
    if isinstance(x, (int, float, complex, np.number)):
        yield path, np.asarray(x)
    elif isinstance(x, np.ndarray):
        if x.dtype.kind in "iufc":
            yield path, x
    elif isinstance(x, (tuple, list)):
        for i, e in enumerate(x):
            yield from _numeric_leaves(e, f"{path}[{i}]", depth + 1)
    elif isinstance(x, dict):
        for k, e in x.items():
            yield from _numeric_leaves(e, f"{path}[{k!r}]", depth + 1)
    elif dataclasses.is_dataclass(x):
        for f in dataclasses.fields(x):
            yield from _numeric_leaves(getattr(x, f.name), f"{path}.{f.name}", depth + 1)


def assert_finite(result: Any) -> None:
    for path, a in _numeric_leaves(result):
        assert np.all(np.isfinite(a)), f"{path} is not finite: {a!r}"[:400]


def _shape_of(x: Any) -> Any:
    if isinstance(x, tuple) and not hasattr(x, "_fields"):
        return tuple(_shape_of(e) for e in x)
    if hasattr(x, "_fields"):  # NamedTuple
        return tuple(_shape_of(e) for e in x)
    return np.shape(x)


ACCEPTED = (RobokinError, ValueError, TypeError)


class Outcome:
    """Counters for the report."""

    examples = 0
    specs: set[str] = set()


def run_example(spec: Spec, data: Any) -> None:
    """Draw one example of ``spec`` with hypothesis' ``data`` and apply the oracle."""
    import hypothesis.strategies as st

    sizes = list(spec.sizes) if spec.sizes is not None else [None, 1, 3] + ([0] if spec.empty else [])
    N = data.draw(st.sampled_from(sizes), label="N") if spec.batch else None
    seed = data.draw(st.integers(0, 2**32 - 1), label="seed")
    ctx = Ctx(N, np.random.default_rng(seed))
    if spec.setup is not None:
        spec.setup(ctx)
    slots = spec.all_args()
    candidates = [(k, a) for k, a in slots if a.bad_kinds(ctx)]
    bad_pick = data.draw(st.integers(-1, len(candidates) - 1), label="corrupted argument")
    bad_key, bad_arg, kind = None, None, None
    if bad_pick >= 0:
        bad_key, bad_arg = candidates[bad_pick]
        kind = data.draw(st.sampled_from(bad_arg.bad_kinds(ctx)), label=f"{bad_arg.name} corruption")
    extreme: set[Any] = set()
    for k, a in slots:
        if a.has_extreme and k != bad_key and data.draw(st.integers(0, 5), label=f"{a.name} extreme") == 0:
            extreme.add(k)
    values: dict[Any, Any] = {}
    for k, a in slots:
        if k == bad_key:
            assert kind is not None  # drawn with bad_key
            values[k] = a.make_bad(kind, ctx)
        elif k in extreme:
            values[k] = a.extreme(ctx)
        else:
            values[k] = a.valid(ctx)
    args = [values[i] for i in range(len(spec.args))]
    kwargs = {k: values[k] for k in spec.kwargs}
    Outcome.examples += 1
    Outcome.specs.add(spec.name)
    what = (f"{spec.name}: N={N}, corrupted={bad_arg.name if bad_arg else None} ({kind}), "
            f"extreme={[a.name for k, a in slots if k in extreme]}")

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):  # numpy's defaults
            try:
                result = spec.fn(*args, **kwargs)
                raised = None
            except ACCEPTED as exc:
                raised = exc
            except Exception as exc:
                raise AssertionError(f"{what}: raised {type(exc).__name__}: {exc}") from exc
    numpy_warnings = [w for w in caught if issubclass(w.category, RuntimeWarning)
                      and not issubclass(w.category, RobokinWarning)]
    assert not numpy_warnings, f"{what}: numpy warning {numpy_warnings[0].message}"

    extreme_named = raised is not None and any(a.named_in(str(raised)) for k, a in slots if k in extreme)
    if bad_arg is not None and bad_arg.name in spec.student:
        from robokin.check import CheckResult

        if extreme_named:  # an extreme instructor argument was rejected first: fine
            return
        assert raised is None, f"{what}: a student answer raised {type(raised).__name__}: {raised}"
        assert isinstance(result, CheckResult) and not result.passed and result.message, (
            f"{what}: expected a failed CheckResult, got {result!r}")
        return
    if bad_arg is not None:
        assert raised is not None, f"{what}: accepted the corrupted argument and returned {result!r}"[:600]
        msg = str(raised)
        assert bad_arg.named_in(msg) or extreme_named, f"{what}: message does not name {bad_arg.name!r}: {msg}"
        return
    if raised is not None:
        msg = str(raised)
        named = [a for k, a in slots if k in extreme and a.named_in(msg)]
        assert extreme and named, f"{what}: valid input raised {type(raised).__name__}: {msg}"
        return
    if spec.finite:
        try:
            assert_finite(result)
        except AssertionError as exc:
            raise AssertionError(f"{what}: {exc}") from None
    if spec.shape is not None:
        want = spec.shape(ctx, values)
        if want is not None:
            got = _shape_of(result)
            assert got == want, f"{what}: result shape {got}, expected {want}"
    if spec.check is not None:
        spec.check(result, ctx, values)


def batch_shape(ctx: Ctx, *core: int) -> tuple[int, ...]:
    """``core`` with the batch dimension in front when the example is batched."""
    return core if ctx.N is None else (ctx.N, *core)


def math_isfinite(x: float) -> bool:
    return math.isfinite(x)
