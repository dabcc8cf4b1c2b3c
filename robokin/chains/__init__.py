"""Serial kinematic chains: one model for symbolic derivation, fast numerics and views.

Public API
----------
SerialChain
    The chain: :meth:`~SerialChain.fk`, :meth:`~SerialChain.frames`,
    :meth:`~SerialChain.jacobian`, manipulability, symbolic results, lambdify.
Tx, Ty, Tz, Rx, Ry, Rz, Fixed
    Elementary transforms (constants, or joints when given a joint name).
from_dh, from_modified_dh, from_link_table
    Builders from standard DH, modified (Craig) DH and link-transform tables.
Chain, DrawableChain
    Typing protocols: what the solvers and the views read from a chain.

:mod:`robokin.chains.reference` holds forward kinematics and the geometric Jacobian as the
book writes them (a product of link transforms; one column per joint), for reading; the
engine of :class:`SerialChain` is tested against it.
"""

from robokin.chains.builders import from_dh, from_link_table, from_modified_dh
from robokin.chains.chain import SerialChain
from robokin.chains.elements import Element, Fixed, Rx, Ry, Rz, Tx, Ty, Tz
from robokin.chains.protocol import Chain, DrawableChain

__all__ = [
    "SerialChain",
    "Element",
    "Tx",
    "Ty",
    "Tz",
    "Rx",
    "Ry",
    "Rz",
    "Fixed",
    "from_dh",
    "from_modified_dh",
    "from_link_table",
    "Chain",
    "DrawableChain",
]
