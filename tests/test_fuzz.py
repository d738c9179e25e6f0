"""Fuzzing ``core.simplify`` with random and adversarial sketches (a few examples of each
kind here; ``make fuzz`` runs 10,000), and the regressions fuzzing found."""

from __future__ import annotations

import numpy as np
import pytest
from fuzz_sketches import KINDS, check
from hypothesis import HealthCheck, given, settings

EXAMPLES = 25  # per kind, so that CI runs a few hundred


@pytest.mark.timeout(600)
@pytest.mark.parametrize("kind", sorted(KINDS))
def test_fuzz_kind(kind):
    strategy, share = KINDS[kind]

    @settings(max_examples=max(2, int(EXAMPLES * share)), deadline=None, database=None,
              suppress_health_check=list(HealthCheck))
    @given(strategy)
    def run(strokes):
        assert check(strokes) in ("simplified", "refused")

    run()


def test_fuzz_check_reports_refusals():
    """The checker tells a refused sketch from a simplified one (so counts can mean
    something): NaN-only strokes leave nothing to draw."""
    assert check([np.array([[np.nan, 0.0], [1.0, np.inf]])]) == "refused"
    assert check([np.array([[0.0, 0.0], [10.0, 0.0]])]) == "simplified"
