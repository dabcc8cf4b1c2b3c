"""Plain data between the student's kernel and the grader's kernel, as JSON.

This file runs on both sides of the bridge: the grader's kernel imports it, and
the grader sends its source text to the student's kernel, where it is executed
into a module of its own (``sys.modules['_robokin_bridge']``). It therefore
imports nothing of the course but numpy (and sympy and robokin when a value
needs them), and it never evaluates text: sympy expressions travel as ``srepr``
text read back by a whitelist parser (:func:`parse_sympy`), robokin objects by
their fields, arrays as raw bytes of a whitelisted dtype.

What the student's kernel sends is untrusted input: :func:`decode` enforces a
depth limit, size caps and a type whitelist, and raises :class:`BridgeError`
(with a message for the student) on anything else.

Encoded forms (JSON):

=================================  ==============================================
value                              JSON
=================================  ==============================================
None, bool, int, str               themselves (int at most 10**40 in magnitude)
float                              itself, or ``{"$float": "nan" | "inf" | "-inf"}``
list                               a JSON list
tuple, set, frozenset, dict        ``{"$tuple": [...]}``, ``{"$set": [...]}``,
                                   ``{"$frozenset": [...]}``, ``{"$dict": [[k, v], ...]}``
complex                            ``{"$complex": [re, im]}``
numpy array / numpy scalar         ``{"$ndarray": [dtype, shape, base64]}`` /
                                   ``{"$npscalar": [dtype, base64]}``
sympy object                       ``{"$sympy": srepr}``; a Poly ``{"$poly": [srepr, [gens]]}``
a robokin module                   ``{"$module": name}`` (imported on the other side)
a caught warning                   ``{"$warning": [module, category, message, file, line]}``
robokin dataclass / named tuple   ``{"$robokin": [module, class, {field: value}]}``
/ model (:data:`ROBOKIN_MODELS`)
numpy array of strings             ``{"$strarray": [shape, [str, ...]]}``
a function (student's side only)   ``{"$callable": [handle, name, signature, module]}``
a proxy handed back (grader only)  ``{"$handle": handle}`` (the student's own function)
anything else                      ``{"$opaque": type name}`` (not plain data)
=================================  ==============================================
"""

from __future__ import annotations

import ast
import base64
import dataclasses
import importlib
import json
import math
import sys
import types
import warnings
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import socket

MAX_DEPTH = 24
MAX_ITEMS = 200_000            # elements of one list/tuple/dict/set
MAX_ARRAY_ELEMENTS = 5_000_000  # elements of one numpy array
MAX_TEXT = 1_000_000           # characters of one string or srepr
MAX_INT = 10**40
MAX_SYMPY_NODES = 200_000
MAX_SYMPY_EXPONENT = 1000

DTYPES = frozenset({
    "bool", "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64",
    "float16", "float32", "float64", "complex64", "complex128",
})

#: robokin classes that are not dataclasses but are rebuilt from constructor arguments
#: (``module.Class``: attribute names passed as keyword arguments of the constructor).
ROBOKIN_MODELS = {
    "robokin.parallel.planar_3rpr.Planar3RPR": ("base_anchors", "platform_anchors", "stroke", "name"),
    "robokin.chains.chain.SerialChain": ("elements", "limits", "tool", "frame_names", "name"),
}

#: sympy names a ``srepr`` text may call, and the names it may use as constants.
SYMPY_CALLS = frozenset({
    "Symbol", "Integer", "Rational", "Float", "Add", "Mul", "Pow", "Tuple",
    "sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "atan2", "acot",
    "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "exp", "log", "Abs", "sign",
    "re", "im", "conjugate", "floor", "ceiling", "Min", "Max", "Piecewise", "ExprCondPair",
    "Eq", "Ne", "Lt", "Le", "Gt", "Ge", "StrictLessThan", "StrictGreaterThan",
    "LessThan", "GreaterThan", "Equality", "Unequality", "And", "Or", "Not",
    "MutableDenseMatrix", "ImmutableDenseMatrix", "Matrix",
})
SYMPY_CONSTANTS = frozenset({"pi", "E", "I", "oo", "zoo", "nan", "true", "false", "EulerGamma"})
SYMPY_KEYWORDS = frozenset({
    "real", "positive", "negative", "nonnegative", "nonpositive", "integer", "rational",
    "complex", "finite", "nonzero", "zero", "commutative", "extended_real", "precision",
})


class BridgeError(Exception):
    """A value that cannot cross the bridge (the message is meant for the student)."""


def type_name(value) -> str:
    cls = type(value)
    module = getattr(cls, "__module__", "") or ""
    return cls.__qualname__ if module in ("builtins", "") else f"{module}.{cls.__qualname__}"


# ---------------------------------------------------------------- encode
def encode(value, registry=None, depth=0):
    """``value`` as JSON-able data; functions go into ``registry`` (a dict) when one is given."""
    if depth > MAX_DEPTH:
        raise BridgeError(f"nested more than {MAX_DEPTH} levels deep")
    if value is None or isinstance(value, (bool, str)):
        if isinstance(value, str) and len(value) > MAX_TEXT:
            raise BridgeError(f"a string of {len(value)} characters (at most {MAX_TEXT})")
        return value
    if isinstance(value, int) and type(value) is int:
        if abs(value) > MAX_INT:
            raise BridgeError("an integer larger than 10**40")
        return value
    if type(value) is float:
        if math.isfinite(value):
            return value
        return {"$float": "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")}
    if type(value) is complex:
        return {"$complex": [encode(value.real), encode(value.imag)]}
    numpy = sys.modules.get("numpy")
    if numpy is not None and isinstance(value, (numpy.ndarray, numpy.generic)):
        return _encode_numpy(value, numpy)
    if type(value) is list:
        _count(value)
        return [encode(v, registry, depth + 1) for v in value]
    if type(value) in (tuple, set, frozenset):
        _count(value)
        items = list(value)
        return {f"${type(value).__name__}": [encode(v, registry, depth + 1) for v in items]}
    if type(value) is dict:
        _count(value)
        return {"$dict": [[encode(k, registry, depth + 1), encode(v, registry, depth + 1)]
                          for k, v in value.items()]}
    return _encode_object(value, registry, depth)


def _encode_numpy(value, numpy):
    """A numpy array (of strings, or of a dtype of :data:`DTYPES`) or numpy scalar as data."""
    if isinstance(value, numpy.ndarray) and value.dtype.kind == "U":
        if value.size > MAX_ITEMS or value.dtype.itemsize // 4 > MAX_TEXT // 100:
            raise BridgeError(f"a numpy array of {value.size} strings")
        return {"$strarray": [list(value.shape), [str(v) for v in value.ravel().tolist()]]}
    dtype = value.dtype.name
    if isinstance(value, numpy.ndarray):
        if dtype not in DTYPES:
            raise BridgeError(f"a numpy array of dtype {dtype}")
        if value.size > MAX_ARRAY_ELEMENTS:
            raise BridgeError(f"a numpy array of {value.size} elements")
        data = numpy.ascontiguousarray(value, dtype=value.dtype.newbyteorder("<"))
        return {"$ndarray": [dtype, list(value.shape), base64.b64encode(data.tobytes()).decode()]}
    if dtype not in DTYPES:
        raise BridgeError(f"a numpy scalar of dtype {dtype}")
    raw = numpy.asarray(value, dtype=value.dtype.newbyteorder("<")).tobytes()
    return {"$npscalar": [dtype, base64.b64encode(raw).decode()]}


def _encode_object(value, registry, depth):
    """A value that is no plain data, collection or numpy value: a sympy object, a robokin
    module, a caught warning, a robokin object, a function (into ``registry``), or opaque."""
    sympy = sys.modules.get("sympy")
    if sympy is not None and isinstance(value, sympy.Basic):
        return _encode_sympy(value, sympy)
    if sympy is not None and isinstance(value, sympy.MatrixBase):
        return {"$sympy": _srepr(value, sympy)}
    if isinstance(value, types.ModuleType):
        name = getattr(value, "__name__", "")
        if isinstance(name, str) and (name == "robokin" or name.startswith("robokin.")):
            return {"$module": name[:200]}
    if isinstance(value, warnings.WarningMessage):
        category = value.category
        return {"$warning": [str(getattr(category, "__module__", ""))[:200],
                             str(getattr(category, "__qualname__", ""))[:200],
                             str(value.message)[:2000], str(value.filename)[:500], int(value.lineno or 0)]}
    module = getattr(type(value), "__module__", "") or ""
    if module.startswith("robokin.") or module == "robokin":
        state = _robokin_state(value)
        if state is not None:
            return {"$robokin": [module, type(value).__qualname__,
                                 {k: encode(v, registry, depth + 1) for k, v in state.items()}]}
    handle = getattr(value, "__robokin_handle__", None) if callable(value) else None
    if type(handle) is int:   # the grader hands a student's function back to the student's kernel
        return {"$handle": handle}
    if registry is not None and callable(value) and not isinstance(value, type):
        handle = len(registry)
        registry[handle] = value
        return {"$callable": [handle, str(getattr(value, "__qualname__", getattr(value, "__name__", "")))[:200],
                              _parameters(value), str(getattr(value, "__module__", "") or "")[:200]]}
    return {"$opaque": type_name(value)[:200]}


def _parameters(function) -> list | None:
    """``[[name, kind, has default], ...]`` of a function's signature (None if unknown)."""
    import inspect

    try:
        signature = inspect.signature(function)
    except (TypeError, ValueError):
        return None
    return [[p.name[:100], int(p.kind), p.default is not p.empty] for p in list(signature.parameters.values())[:50]]


def signature_of(parameters):
    """An ``inspect.Signature`` from :func:`_parameters`' data (None if malformed)."""
    import inspect

    if not isinstance(parameters, list) or len(parameters) > 50:
        return None
    try:
        return inspect.Signature([
            inspect.Parameter(name, inspect._ParameterKind(kind),
                              default=... if has_default else inspect.Parameter.empty)
            for name, kind, has_default in parameters
            if isinstance(name, str) and name.isidentifier() and isinstance(kind, int) and isinstance(has_default, bool)
        ])
    except (TypeError, ValueError):
        return None


def _count(items) -> None:
    if len(items) > MAX_ITEMS:
        raise BridgeError(f"a {type(items).__name__} of {len(items)} items (at most {MAX_ITEMS})")


def _srepr(value, sympy) -> str:
    text = sympy.srepr(value)
    if len(text) > MAX_TEXT:
        raise BridgeError(f"a sympy expression of {len(text)} characters")
    return text


def _encode_sympy(value, sympy):
    if isinstance(value, sympy.Poly):
        return {"$poly": [_srepr(value.as_expr(), sympy), [_srepr(g, sympy) for g in value.gens]]}
    return {"$sympy": _srepr(value, sympy)}


def _is_namedtuple(cls) -> bool:
    return isinstance(cls, type) and issubclass(cls, tuple) and isinstance(getattr(cls, "_fields", None), tuple)


def _robokin_state(value):
    if _is_namedtuple(type(value)):
        return {name: getattr(value, name) for name in type(value)._fields}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: getattr(value, f.name) for f in dataclasses.fields(value) if f.init}
    key = f"{type(value).__module__}.{type(value).__qualname__}"
    if key in ROBOKIN_MODELS:
        return {name: getattr(value, name) for name in ROBOKIN_MODELS[key]}
    return None


# ---------------------------------------------------------------- decode
def decode(data, make_callable=None, depth=0, handles=None):
    """The value ``data`` (from :func:`encode`) stands for; :class:`BridgeError` if not allowed.

    ``make_callable(handle, name)`` makes a proxy of a function; without it a
    function is an error. An ``$opaque`` value becomes an :class:`Untransferable`.
    A tagged value (``{"$tag": body}``) is decoded by the function :data:`DECODERS`
    holds for its tag.
    """
    if depth > MAX_DEPTH:
        raise BridgeError(f"nested more than {MAX_DEPTH} levels deep")
    if isinstance(data, list):
        _count(data)
        return [decode(v, make_callable, depth + 1, handles) for v in data]
    if not isinstance(data, dict) or len(data) != 1:
        return _decode_plain(data)
    (tag, body), = data.items()
    decoder = DECODERS.get(tag)
    if decoder is None:
        raise BridgeError(f"unknown kind of data {str(tag)[:40]!r}")
    return decoder(body, make_callable, depth, handles)


def _decode_plain(data):
    """None, a bool, an int, a float or a str as it is (within the caps); anything else is malformed."""
    if data is None or isinstance(data, (bool, float)):
        return data
    if isinstance(data, int):
        if abs(data) > MAX_INT:
            raise BridgeError("an integer larger than 10**40")
        return data
    if isinstance(data, str):
        if len(data) > MAX_TEXT:
            raise BridgeError(f"a string of {len(data)} characters")
        return data
    raise BridgeError(f"malformed data ({type(data).__name__})")


def _decode_items(body, what, make_callable, depth, handles) -> list:
    if not isinstance(body, list):
        raise BridgeError(f"malformed {what}")
    _count(body)
    return [decode(v, make_callable, depth + 1, handles) for v in body]


def _decode_tuple(body, make_callable, depth, handles):
    return tuple(_decode_items(body, "collection", make_callable, depth, handles))


def _decode_set(body, make_callable, depth, handles):
    return set(_decode_items(body, "collection", make_callable, depth, handles))


def _decode_frozenset(body, make_callable, depth, handles):
    return frozenset(_decode_items(body, "collection", make_callable, depth, handles))


def _decode_dict(body, make_callable, depth, handles):
    if not isinstance(body, list):
        raise BridgeError("malformed dict")
    _count(body)
    out = {}
    for pair in body:
        if not isinstance(pair, list) or len(pair) != 2:
            raise BridgeError("malformed dict item")
        key = decode(pair[0], None, depth + 1)
        try:
            hash(key)
        except TypeError as exc:
            raise BridgeError(f"a dict key of type {type(key).__name__}") from exc
        out[key] = decode(pair[1], make_callable, depth + 1, handles)
    return out


def _decode_float(body, make_callable, depth, handles):
    if body not in ("nan", "inf", "-inf"):
        raise BridgeError("malformed float")
    return float(body)


def _decode_complex(body, make_callable, depth, handles):
    if not (isinstance(body, list) and len(body) == 2):
        raise BridgeError("malformed complex")
    re_part, im_part = (decode(v, None, depth + 1) for v in body)
    if not all(isinstance(v, (int, float)) for v in (re_part, im_part)):
        raise BridgeError("malformed complex")
    return complex(re_part, im_part)


def _decode_ndarray(body, make_callable, depth, handles):
    return _decode_array(body)


def _decode_string_array(body, make_callable, depth, handles):
    import numpy

    if not (isinstance(body, list) and len(body) == 2 and isinstance(body[0], list)
            and isinstance(body[1], list) and len(body[1]) <= MAX_ITEMS and len(body[0]) <= 32
            and all(isinstance(n, int) and not isinstance(n, bool) and n >= 0 for n in body[0])
            and all(isinstance(v, str) and len(v) <= MAX_TEXT // 100 for v in body[1])):
        raise BridgeError("malformed array of strings")
    size = 1
    for n in body[0]:
        size *= n
    if size != len(body[1]):
        raise BridgeError("malformed array of strings")
    return numpy.array(body[1], dtype=str).reshape(body[0])


def _decode_numpy_scalar(body, make_callable, depth, handles):
    if not (isinstance(body, list) and len(body) == 2):
        raise BridgeError("malformed numpy scalar")
    array = _decode_array([body[0], [], body[1]])
    return array[()]


def _decode_sympy(body, make_callable, depth, handles):
    return parse_sympy(body)


def _decode_polynomial(body, make_callable, depth, handles):
    if not (isinstance(body, list) and len(body) == 2 and isinstance(body[1], list) and len(body[1]) <= 50):
        raise BridgeError("malformed polynomial")
    import sympy

    expr = parse_sympy(body[0])
    gens = [parse_sympy(g) for g in body[1]]
    if not all(isinstance(g, sympy.Symbol) for g in gens):
        raise BridgeError("a polynomial whose generators are not symbols")
    return sympy.Poly(expr, *gens)


def _decode_callable(body, make_callable, depth, handles):
    if make_callable is None:
        raise BridgeError("a function cannot be passed here")
    if not (isinstance(body, list) and len(body) in (2, 3, 4) and isinstance(body[0], int)
            and isinstance(body[1], str)):
        raise BridgeError("malformed function handle")
    proxy = make_callable(body[0], body[1][:200])
    if len(body) == 4 and isinstance(body[3], str):
        try:   # where the function says it comes from (a claim of the student's kernel)
            proxy.__robokin_module__ = body[3][:200]
        except AttributeError:
            pass
    signature = signature_of(body[2]) if len(body) >= 3 else None
    if signature is not None:
        try:
            proxy.__signature__ = signature
        except AttributeError:
            pass
    return proxy


def _decode_handle(body, make_callable, depth, handles):
    if handles is None or type(body) is not int or body not in handles:
        raise BridgeError("a function handle where none is expected")
    return handles[body]


def _decode_module(body, make_callable, depth, handles):
    if not (isinstance(body, str) and (body == "robokin" or body.startswith("robokin."))
            and all(part.isidentifier() for part in body.split("."))):
        raise BridgeError("not a robokin module")
    try:
        return importlib.import_module(body)
    except ImportError as exc:
        raise BridgeError(f"no robokin module {body[:80]}") from exc


def _decode_warning(body, make_callable, depth, handles):
    if not (isinstance(body, list) and len(body) == 5 and all(isinstance(v, str) for v in body[:4])
            and type(body[4]) is int):
        raise BridgeError("malformed warning")
    module_name, class_name, message, filename, lineno = body
    if module_name == "builtins" and class_name.isidentifier():
        import builtins

        category = getattr(builtins, class_name, None)
    elif module_name == "robokin.errors" and class_name.isidentifier():
        category = getattr(importlib.import_module("robokin.errors"), class_name, None)
    else:
        category = None
    if not (isinstance(category, type) and issubclass(category, Warning)):
        category = UserWarning
    return warnings.WarningMessage(category(message), category, filename, lineno)


def _decode_opaque(body, make_callable, depth, handles):
    return Untransferable(str(body)[:200])


def _decode_array(body):
    import numpy

    if not (isinstance(body, list) and len(body) == 3 and isinstance(body[0], str)
            and isinstance(body[1], list) and isinstance(body[2], str)):
        raise BridgeError("malformed numpy array")
    dtype, shape, text = body
    if dtype not in DTYPES:
        raise BridgeError(f"a numpy array of dtype {dtype[:40]}")
    if len(shape) > 32 or not all(isinstance(n, int) and not isinstance(n, bool) and 0 <= n for n in shape):
        raise BridgeError("malformed array shape")
    size = 1
    for n in shape:
        size *= n
    if size > MAX_ARRAY_ELEMENTS:
        raise BridgeError(f"a numpy array of {size} elements")
    kind = numpy.dtype(dtype).newbyteorder("<")
    if len(text) > 4 * (size * kind.itemsize + 2) // 3 + 4:
        raise BridgeError("malformed numpy array data")
    raw = base64.b64decode(text.encode(), validate=True)
    if len(raw) != size * kind.itemsize:
        raise BridgeError("numpy array data of the wrong length")
    return numpy.frombuffer(raw, dtype=kind).astype(numpy.dtype(dtype)).reshape(shape)


def _decode_robokin(body, make_callable, depth, handles):
    if not (isinstance(body, list) and len(body) == 3 and isinstance(body[0], str)
            and isinstance(body[1], str) and isinstance(body[2], dict)):
        raise BridgeError("malformed robokin object")
    module_name, class_name, fields = body
    if not (module_name == "robokin" or module_name.startswith("robokin.")) or "." in class_name:
        raise BridgeError(f"not a robokin class: {module_name[:80]}.{class_name[:80]}")
    try:
        cls = getattr(importlib.import_module(module_name), class_name)
    except (ImportError, AttributeError) as exc:
        raise BridgeError(f"no robokin class {module_name[:80]}.{class_name[:80]}") from exc
    key = f"{module_name}.{class_name}"
    if _is_namedtuple(cls):
        allowed = set(cls._fields)
    elif dataclasses.is_dataclass(cls):
        allowed = {f.name for f in dataclasses.fields(cls) if f.init}
    elif key in ROBOKIN_MODELS:
        allowed = set(ROBOKIN_MODELS[key])
    else:
        raise BridgeError(f"{key} cannot be rebuilt from data")
    if set(fields) != allowed:
        raise BridgeError(f"{key} with fields {sorted(fields)[:10]} (expected {sorted(allowed)})")
    values = {name: decode(value, None, depth + 1) for name, value in fields.items()}
    try:
        return cls(**values)
    except Exception as exc:
        raise BridgeError(f"{class_name} could not be rebuilt: {type(exc).__name__}: {exc}") from exc


#: The decoder of each tag of a tagged value (``{"$tag": body}``): ``(body, make_callable,
#: depth, handles) -> value``, raising :class:`BridgeError` on a malformed body.
DECODERS = {
    "$tuple": _decode_tuple, "$set": _decode_set, "$frozenset": _decode_frozenset, "$dict": _decode_dict,
    "$float": _decode_float, "$complex": _decode_complex,
    "$ndarray": _decode_ndarray, "$strarray": _decode_string_array, "$npscalar": _decode_numpy_scalar,
    "$sympy": _decode_sympy, "$poly": _decode_polynomial, "$robokin": _decode_robokin,
    "$callable": _decode_callable, "$handle": _decode_handle, "$module": _decode_module,
    "$warning": _decode_warning, "$opaque": _decode_opaque,
}


class Untransferable:
    """Stands for an answer that is not plain data: any use of it raises a clear error."""

    __slots__ = ("_what", "_name")

    def __init__(self, what: str, name: str | None = None) -> None:
        object.__setattr__(self, "_what", what)
        object.__setattr__(self, "_name", name)

    def _fail(self, *args, **kwargs):
        who = f"answer `{self._name}`" if self._name else "the answer"
        raise BridgeError(f"{who} is not plain data (a {self._what}): the grader cannot use it")

    def __repr__(self) -> str:
        return f"<answer that is not plain data: a {self._what}>"

    def __getattr__(self, name):
        if name.startswith("__") and name.endswith("__"):
            raise AttributeError(name)
        self._fail()

    __call__ = __array__ = __iter__ = __len__ = __getitem__ = __bool__ = __float__ = __int__ = _fail
    __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = __matmul__ = __rmatmul__ = _fail
    __truediv__ = __rtruediv__ = __pow__ = __neg__ = __lt__ = __le__ = __gt__ = __ge__ = _fail
    __eq__ = __ne__ = _fail
    # unhashable, as ``__eq__`` is ``_fail``; mypy wants a method in object's ``__hash__`` slot
    __hash__ = None  # type: ignore[assignment]


# ---------------------------------------------------------------- sympy
def parse_sympy(text):
    """A sympy object from its ``srepr`` text, without ``eval``: only whitelisted calls."""
    if not isinstance(text, str) or len(text) > MAX_TEXT:
        raise BridgeError("malformed sympy expression")
    import sympy

    try:
        tree = ast.parse(text, mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        raise BridgeError("a sympy expression that cannot be read") from exc
    budget = [MAX_SYMPY_NODES]
    try:
        return _sympy_node(tree.body, sympy, budget, 0)
    except RecursionError as exc:
        raise BridgeError("a sympy expression nested too deeply") from exc


def _sympy_literal(node, budget, depth):
    """Constants and (nested) tuples/lists of constants, for arguments of Symbol, Integer, ..."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float, str, bool, type(None))):
        if isinstance(node.value, int) and not isinstance(node.value, bool) and abs(node.value) > MAX_INT:
            raise BridgeError("an integer larger than 10**40 in a sympy expression")
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) and isinstance(node.operand, ast.Constant) \
            and isinstance(node.operand.value, (int, float)) and not isinstance(node.operand.value, bool):
        return -_sympy_literal(node.operand, budget, depth)
    raise BridgeError("a sympy expression with something other than numbers and names")


def _sympy_node(node, sympy, budget, depth):
    budget[0] -= 1
    if budget[0] < 0:
        raise BridgeError(f"a sympy expression of more than {MAX_SYMPY_NODES} parts")
    if depth > 200:
        raise BridgeError("a sympy expression nested too deeply")
    if isinstance(node, ast.Name):
        if node.id not in SYMPY_CONSTANTS:
            raise BridgeError(f"a sympy expression using {node.id[:40]!r}")
        return {"true": sympy.true, "false": sympy.false}.get(node.id) or getattr(sympy, node.id)
    if isinstance(node, (ast.List, ast.Tuple)):
        items = [_sympy_node(e, sympy, budget, depth + 1) for e in node.elts]
        return items if isinstance(node, ast.List) else tuple(items)
    if isinstance(node, (ast.Constant, ast.UnaryOp)):
        return _sympy_literal(node, budget, depth)
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in SYMPY_CALLS):
        raise BridgeError("a sympy expression with a call that is not allowed")
    name = node.func.id
    keywords = {}
    for kw in node.keywords:
        if kw.arg not in SYMPY_KEYWORDS:
            raise BridgeError(f"a sympy expression with the option {str(kw.arg)[:40]!r}")
        keywords[kw.arg] = _sympy_literal(kw.value, budget, depth)
    if name in ("Symbol", "Integer", "Rational", "Float"):
        args = [_sympy_literal(a, budget, depth) for a in node.args]
        if name == "Symbol" and not (len(args) == 1 and isinstance(args[0], str) and len(args[0]) <= 100
                                     and all(isinstance(v, bool) for v in keywords.values())):
            raise BridgeError("a malformed sympy Symbol")
        if name in ("Integer", "Rational") and not all(isinstance(a, int) and not isinstance(a, bool) for a in args):
            raise BridgeError(f"a malformed sympy {name}")
        if name == "Float" and not (len(args) == 1 and isinstance(args[0], (str, float, int))
                                    and len(str(args[0])) <= 100):
            raise BridgeError("a malformed sympy Float")
    else:
        args = [_sympy_node(a, sympy, budget, depth + 1) for a in node.args]
        if keywords:
            raise BridgeError(f"a sympy {name} with options")
    if name == "Pow" and len(args) == 2 and getattr(args[1], "is_Integer", False) \
            and abs(int(args[1])) > MAX_SYMPY_EXPONENT:
        raise BridgeError(f"a sympy power with an exponent above {MAX_SYMPY_EXPONENT}")
    if name == "Matrix":
        name = "MutableDenseMatrix"
    try:
        return getattr(sympy, name)(*args, **keywords)
    except Exception as exc:
        raise BridgeError(f"a sympy {name} that cannot be built: {type(exc).__name__}") from exc


# ---------------------------------------------------------------- the student's side
MARK = "\x1eROBOKIN-BRIDGE "


def _reply(nonce: str, payload) -> None:
    """Student's kernel: ``payload`` as a marked stdout line (``grader_side._Link.request``)."""
    sys.stdout.write(f"\n{MARK}{nonce} {json.dumps(payload, allow_nan=False)}\n")
    sys.stdout.flush()


def _export_entry(name) -> dict:
    """Student's kernel: the declared answer ``name`` of ``__main__``, encoded (or why not)."""
    namespace = sys.modules["__main__"].__dict__
    if name not in namespace:
        return {"missing": True}
    try:
        return {"value": encode(namespace[name], REGISTRY)}
    except BridgeError as exc:
        return {"error": str(exc)[:300], "type": type_name(namespace[name])[:200]}
    except Exception as exc:  # noqa: BLE001 - an answer whose encoding fails is reported
        return {"error": f"{type(exc).__name__}: {str(exc)[:200]}", "type": type_name(namespace[name])[:200]}


def _send_export(channel, names) -> None:
    """Student's kernel: one frame per name (``{"name", "entry"}``), then ``{"done": true}``."""
    for name in names if isinstance(names, list) else []:
        entry = _export_entry(name)
        try:
            send_frame(channel, {"name": str(name), "entry": entry})
        except BridgeError as exc:   # larger than a frame: reported, not sent
            value = sys.modules["__main__"].__dict__.get(name)
            send_frame(channel, {"name": str(name), "entry": {"error": str(exc)[:300],
                                                              "type": type_name(value)[:200]}})
    send_frame(channel, {"done": True})


def _grader_function(handle, name):
    """Student's kernel: a function of the test's, passed to the student's function.

    Calling it asks the grader (over the call channel, :func:`serve`) to run the test's
    function on the (data) arguments; the result comes back as data.
    """
    def call_grader(*args, **kwargs):
        channel = CHANNEL
        if channel is None:
            raise RuntimeError(f"the test's function {name} can be called only while the test runs")
        send_frame(channel, {"callback": int(handle), "args": encode([list(args), dict(kwargs)], REGISTRY)})
        reply = receive_frame(channel)
        if not isinstance(reply, dict) or "value" not in reply:
            error = reply.get("error", "?") if isinstance(reply, dict) else "no reply"
            raise RuntimeError(f"the test's function {name} failed: {error}")
        return decode(reply["value"], _grader_function, handles=REGISTRY)
    call_grader.__name__ = call_grader.__qualname__ = str(name)[:100] or "test_function"
    return call_grader


#: Characters of a call's stdout (and of its stderr) handed to the grader, who shows them under the test.
MAX_OUTPUT = 100_000


class _Capture:
    """A text stream that keeps the first :data:`MAX_OUTPUT` characters written to it."""

    def __init__(self) -> None:
        self.parts: list[str] = []
        self.size = 0

    def write(self, text) -> int:
        text = str(text)
        if self.size < MAX_OUTPUT:
            self.parts.append(text[: MAX_OUTPUT - self.size])
            self.size += len(self.parts[-1])
        return len(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False

    def text(self) -> str:
        return "".join(self.parts)


def _call(handle, arguments) -> dict:
    """Student's kernel: call the function ``handle`` with the encoded arguments; the reply.

    What the function prints (to ``sys.stdout``, ``sys.stderr``: prints, warnings,
    logging) goes with the reply, and the grader shows it under the test, as it
    would be shown had the test run in this kernel.
    """
    import contextlib

    try:
        function = REGISTRY[handle]
        args, kwargs = decode(arguments, _grader_function, handles=REGISTRY)
    except Exception as exc:  # noqa: BLE001
        return {"bridge_error": f"{type(exc).__name__}: {str(exc)[:300]}"}
    stdout, stderr = _Capture(), _Capture()
    reply = _run_captured(function, args, kwargs, stdout, stderr, contextlib)
    for name, stream in (("stdout", stdout), ("stderr", stderr)):
        if stream.size:
            reply[name] = stream.text()
    return reply


def _run_captured(function, args, kwargs, stdout, stderr, contextlib) -> dict:
    try:
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            result = function(*args, **kwargs)
    except BaseException as exc:  # noqa: BLE001 - the student's function raised
        return {"raised": type(exc).__name__[:100], "message": str(exc)[:500]}
    try:
        return {"value": encode(result, REGISTRY)}
    except BridgeError as exc:
        return {"not_data": str(exc)[:300], "type": type_name(result)[:200]}
    except Exception as exc:  # noqa: BLE001 - an encoding that fails is the answer's problem
        return {"not_data": f"{type(exc).__name__}: {str(exc)[:200]}", "type": type_name(result)[:200]}


# ---------------------------------------------------------------- the call channel
#: Bytes of one frame the grader accepts from the student's kernel.
MAX_FRAME = 64_000_000
_HEADER = 4   # a frame: its length (4 bytes, big-endian), then that many bytes of JSON


def send_frame(sock, payload) -> None:
    """Send ``payload`` (JSON-able) as one frame."""
    data = json.dumps(payload, allow_nan=False, separators=(",", ":")).encode()
    if len(data) > MAX_FRAME:
        raise BridgeError(f"a message of {len(data)} bytes (at most {MAX_FRAME})")
    sock.sendall(len(data).to_bytes(_HEADER, "big") + data)


def _receive_exactly(sock, size: int) -> bytes | None:
    buffer = bytearray()
    while len(buffer) < size:
        chunk = sock.recv(min(size - len(buffer), 1 << 20))
        if not chunk:
            return None
        buffer += chunk
    return bytes(buffer)


def receive_frame(sock):
    """One frame's JSON value; None when the other side closed. ``BridgeError`` if malformed."""
    header = _receive_exactly(sock, _HEADER)
    if header is None:
        return None
    size = int.from_bytes(header, "big")
    if size > MAX_FRAME:
        raise BridgeError(f"a message of {size} bytes (at most {MAX_FRAME})")
    data = _receive_exactly(sock, size)
    if data is None:
        return None
    try:
        return json.loads(data)
    except ValueError as exc:
        raise BridgeError("a malformed message") from exc


def serve(path, token):
    """Student's kernel: answer the grader's calls over a Unix socket until the grader closes it.

    One execute request of the grader's starts this; the kernel is busy until the
    grader ends the session (it closes the socket). The grader asks for the declared
    answers (``{"export": names}``: one frame per name back) and calls the student's
    functions (``{"call": handle, "args": ...}``). Each call is one frame each way
    instead of one execute request, so a call costs a fraction of a millisecond. The
    grader stops a call that takes too long by interrupting the kernel; the
    interrupted call replies ``raised KeyboardInterrupt`` and the session goes on
    until the grader closes it.
    """
    import socket

    global CHANNEL
    channel = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        channel.connect(path)
        send_frame(channel, {"hello": token})
        # a request the grader gave up on (it ran late) is not welcome: it ends here
        channel.settimeout(WELCOME_TIMEOUT)
        if receive_frame(channel) != {"welcome": token}:
            return
        channel.settimeout(None)
        CHANNEL = channel
        while True:
            message = receive_frame(channel)
            if isinstance(message, dict) and "export" in message:
                _send_export(channel, message["export"])
            elif isinstance(message, dict) and "call" in message:
                send_frame(channel, _call(message["call"], message.get("args")))
            else:
                return
    except (OSError, BridgeError, KeyboardInterrupt):
        return   # the grader closed the channel, or gave up on a call
    finally:
        CHANNEL = None
        channel.close()


#: The call server's socket while it serves the grader (None outside a session).
CHANNEL: socket.socket | None = None
#: Seconds a call server waits for the grader to welcome it (a request left over from a
#: session the grader gave up on is then not served).
WELCOME_TIMEOUT = 5.0

REGISTRY: dict = {}
