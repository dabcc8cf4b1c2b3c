"""The data codec of the grading bridge (tools/grading/bridge/codec.py), without kernels.

What crosses between the student's kernel and the grader's is plain data: values
round-trip, untrusted input is refused with a :class:`codec.BridgeError` (no code
evaluated, no foreign class, caps on depth and size), and each tag of the encoded
forms has its own decoder (:data:`codec.DECODERS`).
"""

from __future__ import annotations

import inspect
import json

import numpy as np
import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from robokin.models.three_rpr import three_rpr_classic
from robokin.motion.trajectories import Trajectory
from tools.grading.bridge import codec


def through_json(value, registry=None):
    return json.loads(json.dumps(codec.encode(value, registry)))


def test_values_round_trip():
    t = sp.symbols("t", real=True)
    value = {"a": np.arange(6.0).reshape(2, 3), "b": (1, 2.5, None, "x", True), "c": [np.float64(2.0)],
             "e": sp.Rational(1, 2) * t**2 + sp.sqrt(3) * sp.cos(t), "p": sp.Poly(t**3 - 1, t),
             "f": float("nan"), "z": 1 + 2j, "s": {1, 2}, "fs": frozenset({"a"})}
    back = codec.decode(through_json(value))
    assert np.array_equal(back["a"], value["a"]) and back["a"].dtype == np.float64
    assert back["b"] == value["b"] and back["c"][0] == 2.0 and back["z"] == 1 + 2j
    assert back["s"] == {1, 2} and back["fs"] == frozenset({"a"})
    assert sp.simplify(back["e"] - value["e"]) == 0 and back["p"].degree() == 3 and np.isnan(back["f"])
    path = Trajectory(np.zeros((2, 3)), np.ones((2, 3)), np.zeros((2, 3)))
    back = codec.decode(through_json([path, np.array([["ok", "failed"]])]))
    assert isinstance(back[0], Trajectory) and np.array_equal(back[0][1], path[1])
    assert back[1].tolist() == [["ok", "failed"]]
    robot = codec.decode(through_json(three_rpr_classic()))
    assert np.allclose(robot.base_anchors, three_rpr_classic().base_anchors)


plain = st.recursive(
    st.none() | st.booleans() | st.integers(-10**40, 10**40) | st.floats(allow_nan=False) | st.text(max_size=20),
    lambda children: (st.lists(children, max_size=4) | st.tuples(children, children)
                      | st.dictionaries(st.text(max_size=5), children, max_size=4)),
    max_leaves=20)


@given(plain)
def test_plain_data_round_trips_exactly(value):
    assert codec.decode(through_json(value)) == value


@pytest.mark.parametrize("bad", [
    {"$sympy": "__import__('os').system('true')"}, {"$sympy": "Symbol('x').__class__"},
    {"$robokin": ["os", "system", {}]}, {"$ndarray": ["object", [1], ""]},
    {"$ndarray": ["float64", [10**9], ""]}, {"$sympy": "Pow(Integer(2), Integer(10000000))"},
    {"$poly": ["Symbol('x')", ["Integer(1)"]]}, {"$what": 1}, 10**50, {"$tuple": 1, "$set": 2}, (1, 2),
])
def test_untrusted_input_is_refused(bad):
    with pytest.raises(codec.BridgeError):
        codec.decode(bad)


def test_nesting_is_capped():
    deep: list = []
    for _ in range(100):
        deep = [deep]
    with pytest.raises(codec.BridgeError, match="nested more than"):
        codec.decode(deep)


#: a malformed body for each tag, with the start of the message that refuses it
MALFORMED = {
    "$tuple": (1, "malformed collection"), "$set": ("x", "malformed collection"),
    "$frozenset": ({}, "malformed collection"), "$dict": ([[1]], "malformed dict item"),
    "$float": ("1.5", "malformed float"), "$complex": ([1, "i"], "malformed complex"),
    "$ndarray": (["float64", [2], "AAAA"], "numpy array data of the wrong length"),
    "$strarray": ([[3], ["a"]], "malformed array of strings"), "$npscalar": (1, "malformed numpy scalar"),
    "$sympy": ("os.system('true')", ""), "$poly": ("x", "malformed polynomial"),
    "$robokin": (["robokin.motion", "nothing_here", {}], "no robokin class"),
    "$callable": ([0, "f"], "a function cannot be passed here"),
    "$handle": (0, "a function handle where none is expected"), "$module": ("os", "not a robokin module"),
    "$warning": (["builtins", "UserWarning", "m", "f"], "malformed warning"),
}


def test_every_tag_has_a_decoder_and_a_refusal():
    assert set(codec.DECODERS) == set(MALFORMED) | {"$opaque"}
    for tag, (body, message) in MALFORMED.items():
        with pytest.raises(codec.BridgeError, match="^" + message.replace("(", r"\(")):
            codec.decode({tag: body})


def test_a_function_crosses_as_a_handle_with_its_signature():
    registry: dict = {}

    def ik(x, y, phi=0.0):
        return x

    class Proxy:
        def __call__(self, *args):
            return None

    proxy = codec.decode(through_json(ik, registry), lambda handle, name: Proxy())
    assert registry == {0: ik} and str(inspect.signature(proxy)) == "(x, y, phi=Ellipsis)"
    with pytest.raises(codec.BridgeError):
        codec.decode(codec.encode(ik, {}))   # no proxies where the grader expects data
    opaque = codec.decode(codec.encode(object()))
    assert isinstance(opaque, codec.Untransferable)
    with pytest.raises(codec.BridgeError, match="not plain data"):
        np.asarray(opaque) + 1
