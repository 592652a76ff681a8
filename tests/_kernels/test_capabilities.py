"""The engines' capability table (:mod:`jointplay._kernels.capabilities`) and its one reader:
every cell of the table is walked, and the refusals that ask it agree with it."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay._kernels import eom, ids
from jointplay._kernels.capabilities import (
    BACKENDS,
    ENGINES,
    FEATURES,
    FRICTION_FORMS,
    LAW_FORMS,
    engine_of,
    refusal,
)
from jointplay._kernels.lanes.build import lane_layout, lanes_refusal
from jointplay._kernels.lanes.source import LY_GEOM, LY_NC

NEEDS = [*FEATURES, *(f"law:{law}" for law in sorted(LAW_FORMS)),
         *(f"friction:{law}" for law in sorted(FRICTION_FORMS))]  # fmt: skip


@pytest.mark.parametrize("engine", sorted(ENGINES))
@pytest.mark.parametrize("need", NEEDS)
def test_every_cell_of_the_table_is_read_by_the_one_reader(engine: str, need: str) -> None:
    """A need is refused exactly where the table says the engine lacks it; the refusal names
    the engine and the need, and sends it only to engines that have it."""
    own = ENGINES[engine]
    message = refusal(engine, [need])
    if own.has(need):
        assert message is None
        return
    assert message is not None and message.startswith(own.words)
    assert "turn it off" in message
    names = need.partition(":")[2] if ":" in need else FEATURES[need]
    assert names in message
    sent = [e for k, e in ENGINES.items() if k != engine and e.where in message]
    assert sent, message  # somewhere to go: every need of the table runs on some engine
    assert all(e.has(need) for e in sent), message


def test_the_table_says_what_the_engines_do() -> None:
    """The rows as the engines' documentation states them: only the single engine keeps
    trajectories; sustained contact on the single engine and the CPU's implicit lanes only;
    film damping also on the cuda backend's implicit lanes, not on the explicit lanes nor on
    JAX; a Reynolds film on the implicit engines (CPU and cuda), not on the explicit lanes nor on JAX; every engine ideal joints and
    every law family."""
    assert [k for k, e in ENGINES.items() if e.trajectories] == ["single"]
    assert {k for k, e in ENGINES.items() if e.sustained_contact} == {"single", "batch-implicit"}
    assert {k for k, e in ENGINES.items() if e.film_damping} == {
        "single", "batch-implicit", "lanes-implicit"
    }  # fmt: skip
    assert {k for k, e in ENGINES.items() if e.film_model} == {
        "single", "batch-implicit", "lanes-implicit"
    }  # fmt: skip
    assert all(e.ideal_joints and e.laws == LAW_FORMS for e in ENGINES.values())
    assert ENGINES["single"].integrators == ("radau", "rodas4", "dopri5")


def test_every_backend_has_its_engines() -> None:
    from jointplay.execution.backends import BACKENDS as KINDS

    assert set(KINDS) <= set(BACKENDS)
    for kind, engines in BACKENDS.items():
        assert engines["explicit"] in ENGINES and engines["implicit"] in ENGINES
        assert engine_of(kind, "auto") == engines["implicit"]
        single = engine_of(kind, "single")
        assert (single == "single") == (engines["single"] == "single")
    assert engine_of("gpu", "single") == "jax" and engine_of("cuda", "explicit") == "lanes-explicit"


def test_an_unknown_need_is_a_programming_error() -> None:
    with pytest.raises(ValueError, match="unknown need"):
        refusal("single", ["lubrication"])


def test_the_lanes_refusal_reads_the_table(paper_fourbar) -> None:  # type: ignore[no-untyped-def]
    """The single source's lanes refuse what the table's lanes rows lack, with its message."""
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.system import build_system

    linear = ContactModel(film_model="linear")  # the film damping alone, no Reynolds film
    system = build_system(paper_fourbar, linear.joints(paper_fourbar))
    rpar, ipar = eom.pack(system.model)
    rpar = np.atleast_2d(rpar)
    lay = lane_layout(ipar)
    geom = int(lay[LY_GEOM]) + ids.N_GEOM * np.arange(int(lay[LY_NC]))  # each joint's row
    for method, engine in (("explicit", "lanes-explicit"), ("implicit", "lanes-implicit")):
        for column, need in ((ids.G_CAPTURE, "sustained_contact"), (ids.G_FILM, "film_damping")):
            other = ids.G_FILM if column == ids.G_CAPTURE else ids.G_CAPTURE
            lanes = rpar.copy()
            lanes[:, geom + other] = 0.0
            lanes[:, geom[1] + column] = 1e-4 if need == "sustained_contact" else 100.0
            assert lanes_refusal(ipar, lanes, method) == refusal(engine, [need])


def test_the_batch_refusal_reads_the_table() -> None:
    from jointplay.dynamics.batch import _check_implicit_only
    from jointplay.errors import SettingError
    from jointplay.execution.executors import executor

    for kind in ("local", "gpu"):
        runner = executor(kind)
        for method in ("explicit", "implicit"):
            for need in ("sustained_contact", "film_damping"):
                expected = refusal(engine_of(kind, method), [need])
                if expected is None:
                    _check_implicit_only([need], method, runner)
                    continue
                with pytest.raises(SettingError) as refused:
                    _check_implicit_only([need], method, runner)
                assert str(refused.value).startswith(ENGINES[engine_of(kind, method)].words)
