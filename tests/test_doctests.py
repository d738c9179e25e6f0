"""The examples in core's docstrings run and give what they say."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import core

MODULES = sorted(m.name for m in pkgutil.walk_packages(core.__path__, "core.")
                 if not m.name.endswith("__main__"))


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_hold(name):
    module = importlib.import_module(name)
    if not doctest.DocTestFinder().find(module) or not any(
            t.examples for t in doctest.DocTestFinder().find(module)):
        pytest.skip(f"{name} has no examples")  # a module without examples proves nothing
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE,
                             extraglobs={"np": importlib.import_module("numpy")})
    assert result.attempted > 0 and result.failed == 0


def test_the_examples_are_there():
    found = sum(doctest.testmod(importlib.import_module(n)).attempted for n in
                ("core.arrays.geometry", "core.arrays.polylines", "core.curves.bezier",
                 "core.curves.memo"))
    assert found >= 6
