"""Named robot models.

- ``planar_two_link()`` (2 joints): planar RR arm in the x–y plane (tour, first examples).
- ``eth_leg()`` (3): ETH Autonomous Mobile Robots exercise-1 leg (unit lengths).
- ``ur10()`` (6): Universal Robots UR10 (CB3), manufacturer DH parameters; its closed-form
  inverse kinematics (all 8 solutions, any UR table with ``dh=``) is ``ur10_ik(T)``.
- ``baxter_left()`` (7): Rethink Robotics Baxter, left arm (URDF-verified).
- ``ar601_leg()`` (6): AR-601 humanoid leg (hip 3, knee 1, ankle 2); its closed-form
  inverse kinematics (all 8 solutions) is ``ar601_leg_ik(T)``.
- ``genova_arm()`` (7, joint 6 prismatic): the arm of the Genova *Modelling and
  Control of Manipulators* course (chapter 4), from the course's link table.
- ``panda()`` (7): Franka Emika Panda, from its link table (MDH/URDF equivalents).
- ``three_rpr()`` (3 legs): the planar 3-RPR parallel robot of chapter 3, a
  :class:`robokin.parallel.Planar3RPR`; ``three_rpr_classic()`` has six real
  assembly modes (Gosselin, Sefrioui and Richard 1992).

- ``from_urdf(path, base_link, tip_link)``: any serial chain of a URDF file (needs
  yourdfpy); ``robot_description("ur10" | "baxter" | "panda")`` is the path of the
  URDF of those robots in the example-robot-data package (``pip install 'robokin[robots]'``);
  ``visual_meshes(path, base_link, tip_link)`` their visual meshes, frame by frame and
  decimated (for ``robokin.views``: ``views.show(chain, q, meshes="ur10")``).

The serial ones are :class:`robokin.chains.SerialChain` objects with ``.n``,
``.limits``, ``.fk(q)``, ``.jacobian(q)`` and the rest of its API.
"""

from robokin.models.ar601 import ar601_leg
from robokin.models.ar601_ik import AR601IKResult, ar601_leg_ik, ar601_leg_ik_batch
from robokin.models.baxter import baxter_left
from robokin.models.eth_leg import eth_leg
from robokin.models.genova_arm import genova_arm
from robokin.models.panda import panda
from robokin.models.planar import planar_two_link
from robokin.models.three_rpr import three_rpr, three_rpr_classic
from robokin.models.ur10 import ur10
from robokin.models.ur_ik import URIKBatchResult, URIKResult, ur10_ik, ur10_ik_batch
from robokin.models.robot_library import RobotInfo, available_robots
from robokin.models.urdf import ROBOT_DESCRIPTIONS, from_urdf, robot_description
from robokin.models.urdf_meshes import visual_meshes

__all__ = ["planar_two_link", "eth_leg", "ur10", "baxter_left", "ar601_leg", "ar601_leg_ik",
           "ar601_leg_ik_batch", "AR601IKResult", "genova_arm", "panda", "three_rpr",
           "three_rpr_classic", "from_urdf", "robot_description", "ROBOT_DESCRIPTIONS",
           "visual_meshes", "available_robots", "RobotInfo", "ur10_ik", "ur10_ik_batch", "URIKResult",
           "URIKBatchResult"]
