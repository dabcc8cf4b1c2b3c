"""Named robot models built from :class:`robokin.chains.SerialChain`.

=====================  ======  ============================================================
constructor            joints  description
=====================  ======  ============================================================
``planar_two_link()``  2       planar RR arm in the x–y plane (tour / first examples)
``eth_leg()``          3       ETH Autonomous Mobile Robots exercise-1 leg (unit lengths)
``ur10()``             6       Universal Robots UR10 (CB3), manufacturer DH parameters
``baxter_left()``      7       Rethink Robotics Baxter, left arm (URDF-verified)
``ar601_leg()``        6       AR-601 humanoid leg (hip 3, knee 1, ankle 2)
``panda()``            7       Franka Emika Panda, from its link table (MDH/URDF equivalents)
=====================  ======  ============================================================

Every constructor returns a fresh chain with ``.n``, ``.limits``, ``.fk(q)``,
``.jacobian(q)`` and the rest of the :class:`~robokin.chains.SerialChain` API.
"""

from robokin.models.ar601 import ar601_leg
from robokin.models.baxter import baxter_left
from robokin.models.eth_leg import eth_leg
from robokin.models.panda import panda
from robokin.models.planar import planar_two_link
from robokin.models.ur10 import ur10

__all__ = ["planar_two_link", "eth_leg", "ur10", "baxter_left", "ar601_leg", "panda"]
