"""``jointplay animate``: the mechanism over its steady cycle, each pin's play magnified."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any

import typer

from jointplay.cli._app import app
from jointplay.cli._common import (
    ConfigOption,
    DirectionOption,
    GravityOption,
    PresetOption,
    ProgressOption,
    RpmOption,
    StartAngleOption,
    compiling_kernels,
    status,
)
from jointplay.cli._simulation import (
    NO_CONTACT_OPTIONS,
    AtolOption,
    ClearanceOption,
    ContactValues,
    IntegratorOption,
    JointsOption,
    OnsetToleranceOption,
    RampTimeOption,
    RtolOption,
    StartOption,
    run_settings_of,
    with_contact_options,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options
from jointplay.settings.simulation import contact_model, joint_list, over_table


def _opt(help_text: str, *names: str, **kwargs: Any) -> Any:
    return typer.Option(*names, help=help_text, **kwargs)


@app.command("animate")
@with_contact_options()
def animate_command(
    out: Annotated[
        Path,
        _opt(
            "The animation file: FILE.gif (Pillow) or FILE.mp4 (needs ffmpeg). Written only "
            "when the run succeeds; an existing file needs --force.",
            "--out",
            "-o",
        ),
    ],
    force: Annotated[bool, _opt("Replace --out if it exists.", "--force")] = False,
    progress: ProgressOption = True,
    preset: PresetOption = None,
    config: ConfigOption = None,
    rpm: RpmOption = None,
    direction: DirectionOption = None,
    start_angle: StartAngleOption = None,
    gravity: GravityOption = None,
    contact_options: ContactValues = NO_CONTACT_OPTIONS,
    clearance: ClearanceOption = None,
    joints: JointsOption = None,
    start: StartOption = None,
    ramp_time: RampTimeOption = None,
    settle: Annotated[
        int | None,
        _opt(
            "Revolutions simulated before the animated one (default 2, whatever the start: "
            "the animation shows the steady cycle; 0 shows the start-up).",
            "--settle",
        ),
    ] = None,
    rtol: RtolOption = None,
    integrator: IntegratorOption = None,
    atol: AtolOption = None,
    onset_tolerance: OnsetToleranceOption = None,
    magnification: Annotated[
        float | None,
        _opt(
            "Factor on the pin displacements and clearance circles (default: the largest "
            "clearance circle a tenth of the crank, rounded to 1, 2 or 5 x 10^k).",
            "--magnification",
        ),
    ] = None,
    fps: Annotated[int, _opt("Frames per second.", "--fps")] = 20,
    frames: Annotated[int, _opt("Frames over the revolution.", "--frames")] = 72,
    size: Annotated[
        str,
        _opt(
            "Size in pixels, WIDTHxHEIGHT (e.g. 1280x720) or a width (the height at 3:2); "
            "the drawing scales with it.",
            "--size",
        ),
    ] = "960x640",
) -> None:
    """Animate the mechanism over its steady cycle with each pin's play magnified.

    Simulates --settle start-up revolutions and one more, and draws that last revolution:
    links to scale, each clearance joint's clearance circle and pin centre magnified by one
    stated factor. Writes --out (.gif, or .mp4 with ffmpeg installed). Simulation options
    are those of `jointplay simulate` and override the [simulation] table of a --config
    file; --joints none animates the mechanism with ideal joints.
    """
    from jointplay.report.animation import check_animation_settings

    _check_target(out, force)
    check_animation_settings(out, magnification=magnification, fps=fps, frames=frames, size=size)
    with _output_file(out) as partial:
        given = {
            **contact_options, "clearance": clearance, "joints": joints, "start": start,
            "ramp_time": ramp_time, "start_angle": start_angle, "settle": settle, "rtol": rtol,
            "integrator": integrator, "atol": atol,
            "onset_tolerance": onset_tolerance,
        }  # fmt: skip
        result = _simulate(preset, config, rpm, direction, gravity, given, progress)
        from jointplay.report.animation import write_animation

        with status(progress, f"drawing {frames} frames"):
            info = write_animation(
                result,
                partial,
                magnification=magnification,
                fps=fps,
                frames=frames,
                size=size,
            )
    _print(info, out, result)


def _simulate(
    preset: str | None,
    config: Path | None,
    rpm: Any,
    direction: str | None,
    gravity: str | None,
    given: dict[str, Any],
    progress: bool,
) -> Any:
    """Simulate the settle revolutions and the animated one, with the options of simulate."""
    from jointplay.dynamics.cycles import DEFAULT_SETTLE
    from jointplay.dynamics.settings import simulate_run
    from jointplay.io.config import simulation_settings
    from jointplay.units import parse_quantity

    values = over_table(simulation_settings(config, preset), given)
    mechanism = mechanism_from_options(
        preset, config, rpm, direction, values.get("start_angle"), gravity
    )
    ideal = isinstance(values.get("joints"), str) and values["joints"].strip().lower() == "none"
    contact_used = contact_model(values, mechanism)
    clear = (
        []
        if ideal
        else contact_used.joints(
            mechanism,
            joint_list(values.get("joints")),
            clearance=None
            if values.get("clearance") is None
            else parse_quantity(values["clearance"], "m", field="--clearance"),
        )
    )
    if clear:
        from jointplay.dynamics.setup import regime_line

        print(regime_line(contact_used, mechanism, [c.joint for c in clear]))
    run = run_settings_of(values, mechanism, contact_used, settle=DEFAULT_SETTLE)
    settle = run.settle
    where = ", ".join(c.joint for c in clear) or "no joint (ideal joints)"
    with (
        compiling_kernels(),
        status(
            progress,
            f"simulating {settle + 1} revolution(s) of {mechanism.name} with clearance in {where}",
        ),
    ):
        return simulate_run(mechanism, clear, run)


def _check_target(target: Path, force: bool) -> None:
    """``--out`` names a file that may be written: not a folder, and an existing file only
    with ``--force``."""
    text = str(target)
    if target.is_dir():
        raise ConfigError(
            f"--out {text!r} is a folder; give the animation file, e.g. "
            f"{os.path.join(text, 'mechanism.gif')!r}"
        )
    if (target.exists() or target.is_symlink()) and not force:
        raise ConfigError(f"--out {text!r} exists; give another file, or --force to replace it")
    from jointplay.io.output import file_refusal

    if target.exists() and (reason := file_refusal(target)):
        raise ConfigError(f"--out {text!r} {reason}; give another file")


@contextmanager
def _output_file(target: Path) -> Iterator[Path]:
    """Yield a fresh temporary file beside ``target`` (same suffix); on normal exit it
    replaces ``target`` by a rename, on an exception it is removed and ``target`` is left
    as it was. Enter it before computing: an unwritable folder is reported first.
    """
    text = str(target)
    parent = target.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        handle, name = tempfile.mkstemp(
            prefix=f".{target.stem}.partial-", suffix=target.suffix, dir=parent
        )
        os.close(handle)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ConfigError(f"cannot write the animation file {text!r}: {reason}") from None
    partial = Path(name)
    try:
        yield partial
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(partial, 0o666 & ~umask)  # mkstemp makes it private (0600)
        os.replace(partial, target)
    finally:
        partial.unlink(missing_ok=True)


def _print(info: Any, out: Path, result: Any) -> None:
    """What was written, on stdout: frames, magnification, size, the largest displacements."""
    size = info.size_bytes
    shown = f"{size / 1e6:.2f} MB" if size >= 1e6 else f"{size / 1e3:.0f} kB"
    seconds = info.frames / info.fps
    revolution = (
        f"revolution {info.revolution}" if info.revolution is not None else "the simulated time"
    )
    print(
        f"wrote {out}: {info.frames} frames at {info.fps} fps ({seconds:.3g} s) over "
        f"{revolution} of {result.mechanism.name}, pin displacement x {info.magnification:g}, "
        f"{shown}"
    )
    if info.largest_displacement:
        clearances = {c.joint: c.clearance for c in result.system.clearances}
        print(
            "largest pin displacement (clearance): "
            + ", ".join(
                f"{joint} {e * 1e6:.3g} µm ({clearances[joint] * 1e6:.3g} µm)"
                for joint, e in info.largest_displacement.items()
            )
        )
    else:
        print("ideal joints: no pin displacement")
