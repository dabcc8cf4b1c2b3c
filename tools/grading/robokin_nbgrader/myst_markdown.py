"""``MystMarkdown`` (generate_feedback): the task statements' MyST as Markdown."""

from __future__ import annotations

import functools
import re
from pathlib import Path

from nbgrader.preprocessors import NbGraderPreprocessor
from traitlets import Unicode


#: The repository, whose book/references.bib the citations name.
REPOSITORY = Path(__file__).resolve().parents[3]


DIRECTIVE_OPEN = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|:{3,})\{(?P<name>[\w:-]+)\}\s*(?P<argument>.*?)\s*$")
#: The opening fence of a plain code block: ``` or ~~~ (with a language, not a directive).
CODE_OPEN = re.compile(r"^\s*(?P<fence>`{3,}|~{3,})(?!\{)")
#: A MyST role: {cite}`key1,key2`, {doc}`text <target>`.
ROLE = re.compile(r"(?<![\w\\])\{(?P<name>[a-z][\w:-]*)\}(?P<ticks>`+)(?P<body>.+?)(?P=ticks)", re.S)
ADMONITIONS = {"note", "tip", "hint", "important", "warning", "caution", "attention", "danger", "error",
               "seealso"}


@functools.cache
def _bibliography(path: str) -> dict[str, tuple[str, str]]:
    """``{key: (authors, year)}`` of the BibTeX file at ``path`` ("Lynch and Park", "2017")."""
    try:
        from pybtex.database import parse_file

        data = parse_file(path)
    except Exception:  # noqa: BLE001 - without the bibliography a citation shows its key
        return {}
    out = {}
    for key, entry in data.entries.items():
        people = entry.persons.get("author") or entry.persons.get("editor") or []
        names = [" ".join(person.last_names).replace("{", "").replace("}", "") for person in people]
        authors = (names[0] if len(names) == 1 else " and ".join(names) if len(names) == 2
                   else f"{names[0]} et al." if names else key)
        out[key] = (authors, entry.fields.get("year", "n.d."))
    return out


class MystMarkdown(NbGraderPreprocessor):
    """generate_feedback: MyST markup in the text cells becomes plain Markdown, which the page renders.

    The task statements are written for the book (MyST: ``{exercise}``, ``{admonition}``,
    ``{cite}``, ``{doc}``); nbconvert's Markdown shows that markup raw. Here a directive becomes
    what it means in Markdown (an exercise a bold "Exercise c.k" with its text, an admonition a
    quotation under its bold title, the fences of ``{exercise-start}``/``{exercise-end}`` and
    the options go), a citation becomes "(Author, year)" from ``book/references.bib``, and a
    cross-reference its text (a link to a page of the book would not resolve where the page is
    read). Code blocks are left as they are.
    """

    bibliography = Unicode(str(REPOSITORY / "book" / "references.bib"),
                           help="the BibTeX file the {cite} roles name").tag(config=True)

    def preprocess(self, nb, resources):
        name = str(resources.get("nbgrader", {}).get("notebook", "") or "")
        head = name.split("_", 1)[0]
        self._chapter = f"{int(head)}." if head.isdigit() else ""
        self._exercises = 0
        return super().preprocess(nb, resources)

    def preprocess_cell(self, cell, resources, index):
        if cell.cell_type == "markdown" and "{" in cell.source:
            cell.source = self.convert(cell.source)
        return cell, resources

    def convert(self, text: str) -> str:
        """``text`` with its MyST directives and roles as Markdown."""
        if not hasattr(self, "_exercises"):
            self._chapter, self._exercises = "", 0
        return "\n".join(self._blocks(text.split("\n")))

    def _blocks(self, lines: list[str]) -> list[str]:
        out: list[str] = []
        k = 0
        while k < len(lines):
            line = lines[k]
            code = CODE_OPEN.match(line)
            directive = DIRECTIVE_OPEN.match(line)
            if code and not directive:
                end = self._closing(lines, k + 1, code.group("fence"))
                out += lines[k: end + 1]
                k = end + 1
                continue
            if not directive:
                out.append(self._roles(line))
                k += 1
                continue
            end = self._closing(lines, k + 1, directive.group("fence"))
            body = lines[k + 1: end]
            options = {}
            while body and re.match(r"^\s*:[\w-]+:", body[0]):
                option = body.pop(0).strip()[1:]
                options[option.split(":", 1)[0]] = option.split(":", 1)[1].strip()
            out += self._directive(directive.group("name"), self._roles(directive.group("argument")),
                                   options, self._blocks(body), directive.group("indent"))
            k = end + 1
        return out

    @staticmethod
    def _closing(lines: list[str], start: int, fence: str) -> int:
        """The index of the line that closes ``fence`` (the last line if none does)."""
        depth = 0
        for k in range(start, len(lines)):
            stripped = lines[k].strip()
            opening = DIRECTIVE_OPEN.match(lines[k])
            if opening and opening.group("fence") == fence:
                depth += 1
            elif stripped and set(stripped) == {fence[0]} and len(stripped) >= len(fence):
                if depth == 0:
                    return k
                depth -= 1
        return len(lines)

    def _directive(self, name: str, argument: str, options: dict, body: list[str], indent: str) -> list[str]:
        kind = name.split(":")[-1]
        if kind in ("exercise", "exercise-start"):
            self._exercises += 1
            title = f"**Exercise {self._chapter}{self._exercises}**" + (f" ({argument})" if argument else "")
            return [indent + title, "", *body] if body else [indent + title, ""]
        if kind in ("exercise-end", "solution-start", "solution-end", "margin", "only"):
            return body
        if kind == "admonition" or kind in ADMONITIONS:
            title = argument if kind == "admonition" else (kind.capitalize() + (f": {argument}" if argument else ""))
            quoted = [f"{indent}> **{title}**" if title else f"{indent}>", f"{indent}>"]
            quoted += [f"{indent}> {line[len(indent):] if line.startswith(indent) else line}".rstrip() for line in body]
            return [*quoted, ""]
        if kind == "math":
            return [indent + "$$", *body, indent + "$$"]
        if kind in ("figure", "image"):
            return [f"{indent}![{' '.join(body).strip()}]({argument})"]
        if kind in ("code-block", "code", "code-cell"):
            return [indent + "```" + argument, *body, indent + "```"]
        head = [f"{indent}**{argument}**", ""] if argument else []
        return [*head, *body]

    def _roles(self, line: str) -> str:
        return ROLE.sub(self._role, line) if "{" in line else line

    def _role(self, match) -> str:
        name, body = match.group("name"), match.group("body").strip()
        if name.startswith("cite"):
            references = _bibliography(self.bibliography)
            cited = [references.get(key.strip(), (key.strip(), "")) for key in body.split(",") if key.strip()]
            if name in ("cite:t", "cite:ts"):
                return "; ".join(f"{authors} ({year})" if year else authors for authors, year in cited)
            return "(" + "; ".join(f"{authors}, {year}" if year else authors for authors, year in cited) + ")"
        if name == "math":
            return f"${body}$"
        if name == "eq":
            return f"({body})"
        explicit = re.match(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", body, re.S)
        if explicit and explicit.group("text"):
            return explicit.group("text")
        if name in ("doc", "ref", "numref", "term", "download", "any"):
            return body.rsplit("/", 1)[-1].replace("-", " ").replace("_", " ")
        return body
