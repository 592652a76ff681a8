"""Column names of result tables, shared by the nominal analysis and the simulations.

Links are named by their textbook numbers (ground 1, then the moving links in order): a
rotating link k gives ``theta{k}_deg``, ``omega{k}``, ``alpha{k}``; a slider on a ground guide
gives ``{link}_x``, ``{link}_v``, ``{link}_a``; every joint gives ``F_{joint}``.
"""

from __future__ import annotations

from jointplay.model.mechanism import GROUND, Mechanism, PrismaticJoint


def sliders(mechanism: Mechanism) -> list[PrismaticJoint]:
    """Prismatic joints whose guide is the ground (their slider's travel is tabulated)."""
    return [j for j in mechanism.joints if isinstance(j, PrismaticJoint) and j.link_a == GROUND]


def rotating_links(mechanism: Mechanism) -> list[tuple[str, int]]:
    """(name, number) of the moving links other than the crank that are not sliders."""
    slider_links = {j.link_b for j in sliders(mechanism)}
    return [
        (link.name, mechanism.link_number(link.name))
        for link in mechanism.links
        if link.name != mechanism.driver.link and link.name not in slider_links
    ]
