"""Parallel robots (layer 3, next to :mod:`robokin.chains`).

=====================  ==========================================================
class                  description
=====================  ==========================================================
``Planar3RPR``         planar 3-RPR robot: inverse kinematics, all assembly modes
                       of the forward kinematics, inverse Jacobian, singularities
=====================  ==========================================================

Named instances are built in :mod:`robokin.models` (``robokin.models.three_rpr``).
References: Merlet, *Parallel Robots* (2006); Gosselin & Merlet (1994).
"""

from robokin.parallel.planar_3rpr import ForwardKinematicsResult, Planar3RPR

__all__ = ["ForwardKinematicsResult", "Planar3RPR"]
