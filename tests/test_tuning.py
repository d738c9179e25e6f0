"""Tuning in one place (issue 49, item 4): every field of :class:`core.params.Tuning` has a
``#:`` comment that names its entry in ``docs/decisions.md``, and that entry exists."""

from __future__ import annotations

import ast
import re
from dataclasses import fields
from pathlib import Path

from core.params import Tuning

ROOT = Path(__file__).resolve().parents[1]


def field_comments(source: str) -> dict[str, str]:
    """The ``#:`` comment above each field of the Tuning class, joined into one line."""
    tree = ast.parse(source)
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Tuning")
    lines = source.splitlines()
    out = {}
    for node in cls.body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            k, comment = node.lineno - 2, []
            while k >= 0 and lines[k].strip().startswith("#:"):
                comment.insert(0, lines[k].strip()[2:].strip())
                k -= 1
            out[node.target.id] = " ".join(comment)
    return out


def pointers(comment: str) -> list[str]:
    """The headings a comment names: ``decisions: "words of the heading"``.

    >>> pointers('a reach. decisions: "the pen stage"')
    ['the pen stage']
    """
    return re.findall(r'decisions: "([^"]+)"', comment)


def test_every_tuning_field_says_what_it_decides_and_names_its_decisions_entry():
    comments = field_comments((ROOT / "core" / "params.py").read_text())
    headings = [line.lower() for line in (ROOT / "docs" / "decisions.md").read_text()
                .splitlines() if line.startswith("#")]
    assert set(comments) == {f.name for f in fields(Tuning)}
    for name, comment in comments.items():
        named = pointers(comment)
        assert len(comment) > 40 and named, f"{name}: no #: comment naming its entry"
        for words in named:
            assert any(words.lower() in h for h in headings), f"{name}: no entry {words!r}"


def test_the_check_fails_for_a_field_without_a_comment_or_with_a_missing_entry():
    source = '''class Tuning:
    #: a reach. decisions: "no such entry"
    reach: float = 1.0
    bare: float = 2.0
'''
    comments = field_comments(source)
    assert comments["bare"] == "" and pointers(comments["reach"]) == ["no such entry"]
