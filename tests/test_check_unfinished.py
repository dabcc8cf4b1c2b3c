"""Tests of robokin.check.unfinished: a read-only cell goes on past an unfinished answer."""

import pytest

from robokin.check.unfinished import unfinished_note, your_answers


def trapezoid_time(distance, v_max, a_max):  # a student's stub
    raise NotImplementedError()


def test_the_stub_is_named_with_its_task(capsys):
    with your_answers("Task 3"):
        trapezoid_time(1.0, 1.0, 2.0)
        pytest.fail("the block goes on after the error")
    out = capsys.readouterr().out
    assert out.startswith("⚠ your trapezoid_time raised NotImplementedError: finish Task 3 first")
    assert "the notebook goes on" in out


def test_a_missing_name_and_an_error_of_the_cell_itself(capsys):
    with your_answers("Task 5", "Task 6"):
        track  # type: ignore[name-defined]  # noqa: B018, F821 - never defined: its answer cell stopped early
    with your_answers():
        [1][2]
    first, second = capsys.readouterr().out.splitlines()
    assert "name 'track' is not defined" in first and "finish Task 5 and Task 6 first" in first
    assert second.startswith("⚠ the cell raised IndexError: list index out of range on your")


def test_no_error_no_note_and_interrupts_pass(capsys):
    with your_answers("Task 1"):
        value = 2
    assert value == 2 and capsys.readouterr().out == ""
    with pytest.raises(KeyboardInterrupt), your_answers("Task 1"):
        raise KeyboardInterrupt


def test_the_note_of_an_error_without_traceback_and_bad_tasks():
    assert unfinished_note(ValueError("bad shape")) == (
        "⚠ the cell raised ValueError: bad shape on your answers: finish the tasks first; this cell "
        "stops here and the notebook goes on."
    )
    with pytest.raises(TypeError, match="tasks must be strings"):
        your_answers(3)  # type: ignore[arg-type]  # a task that is no string, on purpose


def test_a_half_drawn_figure_is_closed(capsys):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kept = plt.figure()
    with your_answers("Task 2"):
        plt.subplots()
        trapezoid_time(1.0, 1.0, 2.0)
    assert plt.get_fignums() == [kept.number]
    plt.close(kept)
    assert "your trapezoid_time raised NotImplementedError" in capsys.readouterr().out


def test_a_helper_that_raises_is_named_without_your(capsys):
    def via_motion(cubics):
        return cubics[0]

    with your_answers("Task 4"):
        via_motion(None)
    assert capsys.readouterr().out.startswith(
        "⚠ via_motion raised TypeError: 'NoneType' object is not subscriptable on your answers"
    )
