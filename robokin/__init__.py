"""robokin: robot kinematics for teaching.

One model definition serves symbolic derivation (sympy), numeric evaluation
(NumPy, single and batched) and visualisation.  The core (transforms, chains,
models, motion) imports neither matplotlib nor MeshCat.
"""

__version__ = "0.1.0"
