"""The paper report's own logic (the page itself is built in tests/study/test_paper.py and
measured in a browser in tests/report/test_browser.py)."""

from __future__ import annotations

import math

from jointplay.report.paper import AGREEMENT_PCT, claim_counts
from jointplay.study.claims import Claim


def claim(paper: float, ours: float) -> Claim:
    return Claim("section", "a claim", paper, ours, "N", "our source", "why")


def test_every_claim_is_counted_once_under_its_verdict() -> None:
    claims = [
        claim(100.0, 100.0 + AGREEMENT_PCT - 0.01),  # just within: holds
        claim(100.0, 100.0 + AGREEMENT_PCT + 0.01),  # just beyond: differs
        claim(100.0, 50.0),
        claim(math.nan, 3.0),  # the paper gives no number
        claim(7.0, math.nan),  # ours was not computed (a failed run)
    ]
    counts = claim_counts(claims)
    assert list(counts) == ["holds", "differs", "no paper value", "not computed"]
    assert [len(members) for members in counts.values()] == [1, 2, 1, 1]
    assert sum(len(members) for members in counts.values()) == len(claims)
