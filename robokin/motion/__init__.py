"""Motion: inverse kinematics, pose error, Cartesian control, simulation, trajectories.

Layer 4 of robokin: uses :mod:`robokin.transforms` and the chain objects of
:mod:`robokin.chains` / :mod:`robokin.models` (through their ``fk``/``jacobian``
methods) and imports neither matplotlib nor MeshCat.
"""

from robokin.motion.ik import (
    METHODS,
    REASONS,
    DampedLeastSquares,
    GradientObjective,
    IKBatchResult,
    IKHistory,
    IKMethod,
    IKResult,
    JacobianTranspose,
    JointLimitDistance,
    LevenbergMarquardt,
    Manipulability,
    NullSpace,
    PseudoInverse,
    WeightedPseudoInverse,
    solve_ik,
    solve_ik_batch,
    solve_ik_once,
)
from robokin.motion.control import CartesianController, ControlOutput
from robokin.motion.pose_error import pose_error
from robokin.motion.simulate import SimulationLog, simulate
from robokin.motion.sweeps import BatchTrackingLog, initial_condition_sweep, track_position_batch
from robokin.motion.tool import chain_with_tool, rigid_body_jacobian, tool_jacobian
from robokin.transforms import transform_from_rpy as transform_from_rpy  # documented in robokin.transforms
from robokin.motion.joint_trajectory import JOINT_LAWS, joint_trajectory, joint_trajectory_duration
from robokin.motion.pose_trajectory import PoseTrajectory, pose_trajectory
from robokin.motion.trajectories import (
    Trajectory,
    circle_trajectory,
    line_trajectory,
    time_law,
    via_point_trajectory,
)

__all__ = [
    "chain_with_tool",
    "rigid_body_jacobian",
    "tool_jacobian",
    "initial_condition_sweep",
    "track_position_batch",
    "BatchTrackingLog",
    "pose_error",
    "CartesianController",
    "ControlOutput",
    "simulate",
    "SimulationLog",
    "Trajectory",
    "circle_trajectory",
    "line_trajectory",
    "via_point_trajectory",
    "time_law",
    "joint_trajectory",
    "joint_trajectory_duration",
    "JOINT_LAWS",
    "pose_trajectory",
    "PoseTrajectory",
    "solve_ik",
    "solve_ik_once",
    "solve_ik_batch",
    "IKResult",
    "IKHistory",
    "IKBatchResult",
    "REASONS",
    "METHODS",
    "IKMethod",
    "PseudoInverse",
    "JacobianTranspose",
    "WeightedPseudoInverse",
    "DampedLeastSquares",
    "NullSpace",
    "LevenbergMarquardt",
    "JointLimitDistance",
    "Manipulability",
    "GradientObjective",
]
