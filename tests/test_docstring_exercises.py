"""What help() shows a student does not answer the chapter's exercise.

A student may call ``help()`` on any robokin function while a chapter asks to derive what that
function computes. Its text states the contract (what it returns, shapes, units, the textbook
section), not the closed form, the derivation or the verdict the exercise asks for. Each case
names the chapter and a phrase of an answer that a docstring once held.
"""

from __future__ import annotations

import importlib
import pydoc

import pytest

#: (chapter, the object help() is called on, phrases of an answer its text must not hold)
CASES = [
    (1, "robokin.models.eth_leg", ["1 + \\cos\\beta", "sign slip", "both knee"]),
    (1, "robokin.transforms.rotx", ["\\cos\\theta & -\\sin\\theta"]),
    (1, "robokin.transforms.roty", ["-\\sin\\theta & 0 & \\cos\\theta"]),
    (3, "robokin.models.three_rpr", ["\\rho_2^2 = ", "even in", "spurious root", "four real"]),
    (3, "robokin.parallel.planar_3rpr", ["\\rho_i = \\lVert", "harmonics 4 to 8", "(1 + it)",
                                         "C_6 = 0", "\\mathbf{B}_i = \\mathbf{p} +"]),
    (6, "robokin.models.ar601_ik", ["law of", "\\cos q_4 = ", "R_x(q_6)\\,\\mathbf{u}", "±arccos",
                                    "hip axes meet", "two\n   branches"]),
    (6, "robokin.models.ar601", ["intersect", "parallel to x", "contradicts"]),
    (7, "robokin.models.ur_ik", ["\\arccos(d_4", "atan2(|s_5|", "c_3 = ", "d_6\\,\\mathbf{z}_6",
                                 "d_6\\mathbf{z}_6", "\\psi + \\pi/2"]),
    (8, "robokin.chains.screws", ["-\\omega_i \\times q_i", "J_v + [p]", "R^\\mathsf{T} J_\\omega",
                                  "\\cdots e^{[\\mathcal{S}_n]q_n} M", "\\mathrm{Ad}_{T^{-1}}]\\, J_s"]),
    (8, "robokin.chains.SerialChain.screw_axes", ["e^{[\\mathcal{S}_n]q_n}M"]),
    (8, "robokin.chains.SerialChain.space_jacobian", ["J_v + [p]J_\\omega", "\\mathrm{Ad}_{e^"]),
    (8, "robokin.chains.SerialChain.body_jacobian", ["R^\\mathsf{T}J_\\omega", "\\mathrm{Ad}_{T^{-1}}"]),
    (8, "robokin.transforms.skew", ["0 & -v_z & v_y"]),
    (8, "robokin.transforms.angle_axis", ["\\frac{\\sin\\theta}{\\theta}[w]", "\\cos\\theta\\, I + \\sin"]),
    (8, "robokin.transforms.screws", ["(\\theta - \\sin\\theta)[\\omega]^2", "[p] R & R",
                                      "\\cot\\frac{\\theta}{2}", "\\tfrac12 [w]"]),
    (8, "robokin.transforms.transform_log", ["\\cot\\frac{\\theta}{2}", "\\tfrac12 [w]", "G^{-1}"]),
    (9, "robokin.chains.ellipsoids", ["1/\\sigma_i", "left singular vectors", "[-m g; 0]",
                                      "the power"]),
    (9, "robokin.chains.SerialChain.force_ellipsoid", ["dual", "cannot move"]),
    (10, "robokin.motion.trajectories", ["10\\tau^3", "3\\tau^2 - 2\\tau^3"]),
    (10, "robokin.motion.joint_trajectory", ["2\\sqrt{D_i", "D_i/\\dot q_{max}", "\\max_i T_i",
                                             "\\sqrt{\\ddot q_{max,i}^2", "slowest joint"]),
    (10, "robokin.motion.pose_trajectory", ["\\dot s\\,\\mathbf{R}_0\\mathbf{w}"]),
    (10, "robokin.transforms.quaternion_slerp", ["\\sin((1 - s)\\Omega)", "q_0 \\cdot q_1 \\ge 0"]),
]


def _help_text(dotted: str) -> str:
    """The text ``help()`` prints for the object named ``dotted`` (a module, a function, a method)."""
    module_name, _, rest = dotted, "", ""
    while True:
        try:
            obj = importlib.import_module(module_name)
            break
        except ModuleNotFoundError:
            module_name, _, last = module_name.rpartition(".")
            rest = f"{last}.{rest}" if rest else last
    for part in filter(None, rest.split(".")):
        obj = getattr(obj, part)
    return pydoc.plain(pydoc.render_doc(obj))


@pytest.mark.parametrize("chapter, dotted, phrases", CASES, ids=[case[1] for case in CASES])
def test_help_states_the_contract_not_the_answer(chapter, dotted, phrases):
    text = _help_text(dotted)
    shown = [phrase for phrase in phrases if phrase in text]
    assert not shown, f"help({dotted}) answers chapter {chapter}'s exercise: {shown}"
