"""A read-only cell that uses the student's answers goes on when one is unfinished.

A figure, a *Try it yourself* cell or a comparison with robokin calls the
functions and reads the values that the student writes. While an answer is still
the stub (it raises ``NotImplementedError``), or raises for another reason, such
a cell should print one short note and let the notebook go on, not stop on a
traceback::

    from robokin.check.unfinished import your_answers

    with your_answers("Task 3"):
        plot_times = [trapezoid_time(D, 1.0, 2.0) for D in distances]
        ...

prints, for the stub, ``… your trapezoid_time raised NotImplementedError: finish
Task 3 first; this cell stops here and the notebook goes on.``
"""

from __future__ import annotations

import os
import sys
from types import TracebackType

__all__ = ["your_answers", "unfinished_note"]

_LIBRARY_FOLDERS = tuple(
    os.path.normcase(os.path.realpath(folder))
    for folder in {
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))),  # robokin
        sys.prefix,
        sys.base_prefix,
    }
)
_ANONYMOUS = {"<module>", "<lambda>", "<genexpr>", "<listcomp>", "<dictcomp>", "<setcomp>"}


def _raising_function(traceback: TracebackType | None) -> str | None:
    """The innermost named function of the notebook's own code in a traceback, if any.

    The first entry is the block of :class:`your_answers` itself: it is skipped.
    """
    name = None
    traceback = traceback.tb_next if traceback is not None else None
    while traceback is not None:
        code = traceback.tb_frame.f_code
        path = os.path.normcase(os.path.realpath(code.co_filename))
        inside_library = path.startswith(_LIBRARY_FOLDERS)
        if not inside_library and code.co_name not in _ANONYMOUS:
            name = code.co_name
        traceback = traceback.tb_next
    return name


def unfinished_note(error: BaseException, tasks: tuple[str, ...] = ()) -> str:
    """The note printed for an error raised by, or for want of, the student's answers.

    Parameters
    ----------
    error : BaseException
        The exception the cell raised (its traceback names the function).
    tasks : tuple of str, optional
        The tasks whose answers the cell uses, e.g. ``("Task 3",)``.

    Returns
    -------
    str
        ``"⚠ your f raised NotImplementedError: finish Task 3 first; …"`` (a
        function of the notebook that raised another error is named without "your":
        it may be a given helper).
    """
    function = _raising_function(error.__traceback__)
    kind = type(error).__name__
    detail = str(error).strip().splitlines()[0] if str(error).strip() else ""
    what = f"{kind}: {detail}" if detail else kind
    if isinstance(error, NameError):
        cause = f"{detail} (a cell above stopped before it)"
    elif function is not None and isinstance(error, NotImplementedError):
        cause = f"your {function} raised {what}"  # still the stub
    elif function is not None:
        cause = f"{function} raised {what} on your answers"
    else:
        cause = f"the cell raised {what} on your answers"
    todo = f"finish {' and '.join(tasks)} first" if tasks else "finish the tasks first"
    return f"⚠ {cause}: {todo}; this cell stops here and the notebook goes on."


def _open_figures() -> set[int]:
    """The numbers of the open matplotlib figures (none if pyplot is not imported)."""
    pyplot = sys.modules.get("matplotlib.pyplot")
    return set(pyplot.get_fignums()) if pyplot is not None else set()


class your_answers:
    """Run a read-only cell's use of the student's answers; print a note if it raises.

    Parameters
    ----------
    *tasks : str
        The tasks whose answers the cell uses (``"Task 3"``), named in the note.

    Notes
    -----
    Any ``Exception`` raised inside the block ends the block, prints
    :func:`unfinished_note` and is not raised further; ``KeyboardInterrupt`` and
    ``SystemExit`` pass through. A matplotlib figure opened inside the block is
    closed then, so that no half-drawn figure is shown.
    """

    def __init__(self, *tasks: str) -> None:
        for task in tasks:
            if not isinstance(task, str):
                raise TypeError(
                    f"your_answers: tasks must be strings such as 'Task 3', got "
                    f"{type(task).__name__} {task!r}"
                )
        self.tasks = tasks

    def __enter__(self) -> your_answers:
        self._figures = _open_figures()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> bool:
        if error is None or not isinstance(error, Exception):
            return False
        pyplot = sys.modules.get("matplotlib.pyplot")
        if pyplot is not None:
            for number in _open_figures() - self._figures:
                pyplot.close(number)
        print(unfinished_note(error, self.tasks))
        return True
