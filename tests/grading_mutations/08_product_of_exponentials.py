"""Wrong answers that each autograded test of the chapter must reject (``MUTATIONS``,
tests/test_grading_mutations.py), and correct answers written another way that must keep
full marks (``VARIANTS``, tests/benign_variants.py and tests/test_grading_trust.py).

``MUTATIONS``: ``{grade id of a test cell: [(what is wrong, code appended to the answer
cells), ...]}``, at least one per graded test. ``VARIANTS``: ``{grade id of an answer cell:
(how it differs, code appended to that cell)}``: another method, not only other names
(without ``VARIANTS``, the trust suite derives a weaker default: each answer wrapped).
The first line of each variant's code must be ASCII without quotes.
"""

MUTATIONS = {
    "task1_test1": [
        ("degrees for radians", "tool_position = (lambda f: lambda q: f(np.rad2deg(q)))(tool_position)"),
        ("the second link's own angle q2 instead of q1 + q2",
         "def tool_position(q):\n    q1, q2 = q\n"
         "    return np.array([np.cos(q1) + np.cos(q2), np.sin(q1) + np.sin(q2)])"),
    ],
    "task2_test1": [
        ("the transposed Jacobian", "tool_jacobian = (lambda f: lambda q: f(q).T)(tool_jacobian)"),
    ],
}

VARIANTS = {
    "task1_answer1": ("the tool as a sum of complex numbers", """

# written another way: the tool point as the complex number e^(i q1) + e^(i (q1 + q2))
def tool_position(q):
    first, second = np.asarray(q, dtype=float)
    tip = np.exp(1j * first) + np.exp(1j * (first + second))
    return np.array([tip.real, tip.imag])
"""),
    "task2_answer1": ("the Jacobian's columns as i times the complex link vectors", """

# written another way: d/dq_k of e^(i q1) + e^(i (q1 + q2)) is i times the links after joint k
def tool_jacobian(q):
    first, second = np.asarray(q, dtype=float)
    elbow, tip = np.exp(1j * first), np.exp(1j * (first + second))
    columns = [1j * (elbow + tip), 1j * tip]
    return np.array([[column.real for column in columns], [column.imag for column in columns]])
"""),
}
