"""Rotations, homogeneous transforms, Euler/RPY angles, angle–axis and quaternions.

Layer 2 of robokin (see CONTRIBUTING.md). Every function works on floats /
single arrays, on batches (a leading axis ``N``) and, where it makes sense, on
sympy expressions (returning a ``sympy.Matrix``).
"""

from robokin.transforms.angle_axis import (
    angle_axis_from_rotation,
    rotation_exp,
    rotation_from_angle_axis,
    rotation_log,
)
from robokin.transforms.euler import (
    rotation_from_rpy,
    rotation_from_zyz,
    rpy_from_rotation,
    transform_from_rpy,
    zyz_from_rotation,
)
from robokin.transforms.homogeneous import (
    compose,
    rotation_of,
    transform,
    transform_inverse,
    transform_point,
    translation,
    translation_of,
)
from robokin.transforms.quaternions import (
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_multiply,
    quaternion_slerp,
    rotation_from_quaternion,
)
from robokin.transforms.rotations import rotx, roty, rotz, skew, unskew
from robokin.transforms.screws import adjoint, transform_exp, transform_log

__all__ = [
    "rotx",
    "roty",
    "rotz",
    "skew",
    "unskew",
    "transform",
    "translation",
    "transform_inverse",
    "compose",
    "rotation_of",
    "translation_of",
    "transform_point",
    "rotation_from_rpy",
    "rpy_from_rotation",
    "transform_from_rpy",
    "rotation_from_zyz",
    "zyz_from_rotation",
    "rotation_exp",
    "rotation_log",
    "rotation_from_angle_axis",
    "angle_axis_from_rotation",
    "transform_exp",
    "transform_log",
    "adjoint",
    "quaternion_from_rotation",
    "rotation_from_quaternion",
    "quaternion_multiply",
    "quaternion_conjugate",
    "quaternion_slerp",
]
