"""The mechanism of the command line's options (``--preset``, ``--config``, ``--rpm``,
``--direction``, ``--start-angle``, ``--gravity``) and the parser of quantity options: read
by the commands and by ``jointplay explore`` alike (SI inside, a unit on every value)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from jointplay.errors import ConfigError
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.model.mechanism import Mechanism


def mechanism_from_options(
    preset: str | None,
    config: Path | None,
    rpm: str | None = None,
    direction: str | None = None,
    start_angle: str | None = None,
    gravity: str | None = None,
) -> Mechanism:
    """Load the mechanism and apply command-line overrides (validated, SI inside)."""
    from jointplay.io.config import load_mechanism
    from jointplay.model.mechanism import check_start_angle

    mechanism = load_mechanism(preset, config)
    changes: dict[str, Any] = {}
    if rpm is not None:
        changes["speed"] = crank_speed(rpm)
    if direction is not None:
        if direction.lower() not in ("ccw", "cw"):
            raise ConfigError(f"--direction must be ccw or cw, got {direction!r}")
        changes["direction"] = 1 if direction.lower() == "ccw" else -1
    if start_angle is not None:
        changes["start_angle"] = check_start_angle(
            parse_quantity(start_angle, "rad", field="--start-angle"), "--start-angle", start_angle
        )
    if changes:
        mechanism = mechanism.with_driver(**changes)
    if gravity is not None:
        mechanism = mechanism.with_gravity(parse_gravity(gravity))
    return mechanism


#: The fastest crank speed the command line accepts, rev/min (beyond it: a typo).
MAX_RPM = 1e6


def quantity_option(
    text: str, unit: str, option: str, *, example: str, positive: bool = False
) -> float:
    """A quantity option (``--hours "600 h"``, ``--step "1 deg"``) in the SI unit ``unit``.

    The one parser of quantity options: the value must carry a unit (README, "Units and
    conventions"); a bare number is refused with a message that shows the form, e.g.
    ``--hours: '600' has no unit; write it with one, e.g. "600 h"``.

    Args:
        text: the option's value.
        unit: the SI unit to convert to (``"s"``, ``"rad"``, ``"rad/s"``, ...).
        option: the option's name, for messages.
        example: the unit shown in the message's example (``"h"``, ``"deg"``, ``"rpm"``).
        positive: refuse zero and negative values.

    Raises:
        ConfigError: no unit, an unknown unit, the wrong dimension, or not positive.
    """
    value = parse_quantity(text, unit, field=option, example=example)
    if positive and not value > 0:
        raise ConfigError(f"{option} must be positive, got {text!r}")
    return value


def crank_speed(rpm: str) -> float:
    """``--rpm`` in rad/s: a crank speed with a unit (``"200 rpm"``, ``"20.9 rad/s"``),
    positive and at most :data:`MAX_RPM` rev/min.

    Raises:
        ConfigError: a bare number, another dimension, or a speed out of range.
    """
    speed = quantity_option(rpm, "rad/s", "--rpm", example="rpm")
    if not 0 < speed <= MAX_RPM * math.pi / 30.0:
        raise ConfigError(
            f"--rpm must be a positive crank speed up to {MAX_RPM:g} rpm, got {rpm!r}"
        )
    return speed


def parse_gravity(text: str) -> tuple[float, float]:
    """``--gravity``: ``off``, ``on`` (9.80665 m/s² towards -y) or a magnitude towards -y,
    at most :data:`jointplay.model.mechanism.MAX_GRAVITY` (1000 m/s²).

    Raises:
        ConfigError: not a quantity of acceleration, or beyond the bound.
    """
    from jointplay.model.mechanism import check_gravity

    value = text.strip().lower()
    if value in ("off", "none", "0"):
        return (0.0, 0.0)
    if value == "on":
        return (0.0, -9.80665)
    magnitude = abs(parse_quantity(text, "m/s^2", field="--gravity"))
    return check_gravity((0.0, -magnitude), "--gravity", text)
