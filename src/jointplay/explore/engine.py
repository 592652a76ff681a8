"""One simulation of ``jointplay explore``, through the command line's own readers and the
public API, turned into what the page draws; and the download, written by the command line.

:func:`simulate_settings` writes the page's settings as a configuration file and reads it back
as ``jointplay simulate --config`` does (the same mechanism loader, ``[simulation]`` reader,
contact model and joint list, of :mod:`jointplay.settings`, which the commands read with),
then calls :func:`jointplay.simulate` with the command's defaults. :func:`view` takes the
drawing from :func:`jointplay.report.animation.mechanism_frames` (the ``animate`` command's
geometry) and the numbers from :meth:`SimulationResult.summary`, the body of ``summary.json``. :func:`download` runs ``jointplay simulate`` itself on that
configuration, so its summary.json and CSV files are the command's own.
"""

from __future__ import annotations

import io
import math
import os
import subprocess
import sys
import tempfile
import threading
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.errors import ConfigError, IntegrationError
from jointplay.explore.settings import PHYSICAL, Base, Settings, config_data

#: Frames of the mechanism's animation over the analysed revolution.
FRAMES = 90
#: The nominal curves are drawn every this many of their 0.1° rows (0.5°).
NOMINAL_STRIDE = 5
#: The arguments of the download's ``jointplay simulate`` (run in a fresh folder).
COMMAND = ("--config", "settings.toml", "--out", "results", "--no-plots", "--no-progress")
#: The integration steps one view may take (accepted steps, start-up revolutions included):
#: ``SolverOptions.max_steps`` of the page's runs. A view past it is refused with a line that
#: says so, rather than holding the one-at-a-time runner for minutes (measured: 300 000 RODAS4
#: steps take about 12 s and DOPRI5's about 8 s on the 2-core machine; a common view needs
#: 1 000–6 000, the slowest start from rest with ten start-up revolutions 230 000–290 000).
VIEW_MAX_STEPS = 300_000
#: The longest the download's ``jointplay simulate`` may take, s.
DOWNLOAD_TIMEOUT_S = 300.0


def settings_toml(base: Base, settings: Settings) -> str:
    """``settings.toml``: the configuration file of ``settings`` (for ``--config``)."""
    from jointplay.io.config_writer import dumps_toml

    query = "&".join(f"{k}={v}" for k, v in settings.query().items())
    header = (
        f"Written by jointplay explore from {base.source}.\n"
        f"jointplay simulate --config settings.toml simulates what the page showed for\n"
        f"?{query}"
    )
    return dumps_toml(config_data(base, settings), header)


#: Nominal (ideal-joint) analyses kept, by :func:`nominal_key`, newest last.
NOMINAL_CACHE = 16
_NOMINAL: dict[str, Any] = {}


def nominal_key(base: Base, settings: Settings) -> str:
    """What the nominal analysis depends on: the configuration without the joints' clearance
    and fit (an ideal joint has neither) and without the ``[simulation]`` table. Runs that
    differ only there share one nominal analysis (0.1 s of each update saved); its table
    goes to :func:`jointplay.simulate` as ``nominal``."""
    import json

    data = config_data(base, settings)
    data.pop("simulation", None)
    for table in (data.get("joints") or {}).values():
        if isinstance(table, dict):
            table.pop("clearance", None)
            table.pop("fit", None)
    return json.dumps(data, sort_keys=True, default=str)


@dataclass(frozen=True)
class Run:
    """A simulation of the page's settings: the result and what ``simulate`` reports with it."""

    result: Any
    mechanism: Any
    contact: str  # in words
    findings: list[Any]


def simulate_settings(base: Base, settings: Settings) -> Run:
    """Simulate ``settings`` as ``jointplay simulate --config settings.toml`` does."""
    from jointplay import SolverOptions, Start, simulate
    from jointplay.dynamics.diagnostics import simulation_findings
    from jointplay.dynamics.simulate import preferred_integrator
    from jointplay.io.config import simulation_settings
    from jointplay.settings.mechanism import mechanism_from_options
    from jointplay.settings.simulation import (
        check_revolutions,
        contact_model,
        finite_number,
        joint_list,
    )

    with tempfile.TemporaryDirectory(prefix="jointplay-explore-") as folder:
        path = Path(folder) / "settings.toml"
        path.write_text(settings_toml(base, settings), encoding="utf-8")
        mechanism = mechanism_from_options(None, path)
        values = simulation_settings(path)
    key = nominal_key(base, settings)
    nominal = _NOMINAL.get(key, True)  # True: simulate computes it
    names = joint_list(values.get("joints"))
    integrator = None  # Radau; a paper method's own where it holds, as simulate's
    if settings.uniform() is not None or names is None:
        contact = contact_model(values, mechanism)
        clear = contact.joints(mechanism, names)
        described = contact.describe()["text"]
        integrator = preferred_integrator(contact.integrator, mechanism, clear)
    else:  # joints of their own contact or friction: each its contact model, as simulate's
        clear, texts = [], []
        for name in names:
            law, friction = settings.contact_of(name)
            own = {k: v for k, v in values.items() if k not in ("method", "friction")}
            if law != PHYSICAL:
                own["method"] = law
            if friction is not None:
                own["friction"] = friction
            contact = contact_model(own, mechanism)
            clear += contact.joints(mechanism, [name])
            texts.append(f"{name}: {contact.describe()['text']}")
        described = " | ".join(texts)
    mode = str(values.get("start", "steady"))
    ramp = mechanism.driver.period / 4 if mode == "ramp" else 0.0
    turns = finite_number(values, "revolutions", 1.0)
    check_revolutions(turns)
    started = time.perf_counter()
    try:
        result = simulate(
            mechanism,
            clear,
            revolutions=turns,
            settle=int(values.get("settle", 2)),
            start=Start(mode, ramp),  # type: ignore[arg-type]  # validated by Start
            solver=SolverOptions(
                rtol=finite_number(values, "rtol", 1e-6),
                integrator=integrator,
                max_steps=VIEW_MAX_STEPS,
            ),
            nominal=nominal,
        )
    except IntegrationError as exc:
        over = _over_budget(exc, time.perf_counter() - started)
        if over is None:
            raise
        raise over from None
    if result.nominal is not None:
        _NOMINAL.pop(key, None)
        _NOMINAL[key] = result.nominal
        while len(_NOMINAL) > NOMINAL_CACHE:
            _NOMINAL.pop(next(iter(_NOMINAL)))
    return Run(result, mechanism, described, simulation_findings(result.diagnostics, mechanism))


def _over_budget(error: Exception, seconds: float) -> ConfigError | None:
    """The page's line for an integration that ran past :data:`VIEW_MAX_STEPS` (``error``
    is ``simulate``'s, after ``seconds``), or ``None`` for any other failure."""
    if f"SolverOptions.max_steps = {VIEW_MAX_STEPS})" not in str(error):
        return None
    budget = f"{VIEW_MAX_STEPS:,}".replace(",", " ")
    return ConfigError(
        f"this view needs more than {budget} integration steps, the budget of one view "
        f"(stopped after {seconds:.0f} s): take fewer start-up revolutions, a higher crank "
        "speed or another contact law; the download's jointplay simulate is not held to "
        "this budget"
    )


def _list(values: Any, digits: int = 6) -> list[float | None]:
    """Numbers for JSON, to ``digits`` significant digits of the largest (NaN: ``None``)."""
    array = np.asarray(values, dtype=float)
    finite = np.isfinite(array)
    largest = float(np.max(np.abs(array[finite]), initial=0.0))
    if largest > 0:  # round to the digits of the largest value (short JSON, quick)
        array = np.round(array, digits - 1 - math.floor(math.log10(largest)))
    return [v if ok else None for v, ok in zip(array.tolist(), finite.tolist(), strict=True)]


def view(run: Run) -> dict[str, Any]:
    """Everything the page draws for ``run`` (JSON; mm, µm, degrees, N, N·m, rad/s)."""
    from jointplay.report.animation import crank_length, default_magnification, mechanism_frames

    result, mechanism = run.result, run.mechanism
    summary = result.summary()
    out: dict[str, Any] = {
        "status": summary["status"],
        "message": summary["message"],
        "contact": run.contact,
        "peaks": summary["peaks"],
        "nominal_peaks": summary["nominal_peaks"],
        "increase_percent": summary["increase_percent"],
        "periodicity": summary["periodicity"]["verdict"],
        "diagnostics": [finding.as_dict() for finding in run.findings],
        "max_penetration_um": {
            joint: value * 1e6 for joint, value in result.running.max_penetration.items()
        },
        "solver": {
            key: summary["solver"][key]
            for key in ("steps", "rejected_steps", "wall_s")
            if key in summary["solver"]
        },
    }
    clearances = {c.joint: c.clearance for c in result.system.clearances}
    largest = max(clearances.values(), default=0.0)
    magnification = default_magnification(largest, crank_length(mechanism))
    frames = mechanism_frames(result, frames=FRAMES)
    links: list[list[list[list[float | None]]]] = []  # link -> point -> [xs, ys]
    for link in mechanism.links:
        keys = [key for key in frames.points if key[0] == link.name]
        links.append(
            [
                [_list(frames.points[key][:, 0] * 1e3), _list(frames.points[key][:, 1] * 1e3)]
                for key in keys
            ]
        )
    ground = sorted(
        {key for key in frames.points if key[0] not in {lk.name for lk in mechanism.links}}
    )
    out["mechanism"] = {
        "frames": frames.count,
        "revolution": frames.revolution,
        "crank_deg": _list(frames.crank_deg, 5),
        "links": links,
        "ground": [
            [float(frames.points[key][0, 0] * 1e3), float(frames.points[key][0, 1] * 1e3)]
            for key in ground
        ],
        "magnification": magnification,
        "bearings": [
            {
                "joint": bearing.joint,
                "clearance_um": bearing.clearance * 1e6,
                "centre_mm": [
                    _list(bearing.centre[:, 0] * 1e3),
                    _list(bearing.centre[:, 1] * 1e3),
                ],
                "eccentricity_um": [
                    _list(bearing.eccentricity[:, 0] * 1e6),
                    _list(bearing.eccentricity[:, 1] * 1e6),
                ],
            }
            for bearing in frames.bearings
        ],
    }
    period = mechanism.driver.period
    table = result.timeseries
    analysed = table[table["t"] >= result.settle * period * (1 - 1e-12)]
    angle = analysed["crank_deg"].to_numpy() - 360.0 * result.settle
    nominal = result.nominal
    nominal_rows = nominal.iloc[::NOMINAL_STRIDE] if nominal is not None else None
    out["orbits"] = {
        joint: {
            "clearance_um": c * 1e6,
            "x_um": _list(analysed[f"ex_{joint}"].to_numpy() * 1e6),
            "y_um": _list(analysed[f"ey_{joint}"].to_numpy() * 1e6),
        }
        for joint, c in clearances.items()
    }
    quantities = [key for key in result.peaks if key in analysed.columns]
    out["curves"] = {
        "crank_deg": _list(angle, 7),
        "nominal_crank_deg": [] if nominal_rows is None else _list(nominal_rows["crank_deg"], 7),
        "series": {
            key: {
                "values": _list(analysed[key].to_numpy()),
                "nominal": []
                if nominal_rows is None or key not in nominal_rows
                else _list(nominal_rows[key].to_numpy()),
            }
            for key in quantities
        },
    }
    return out


#: How long :meth:`Children.end` waits for a stopped ``jointplay simulate`` before killing it, s.
END_WAIT_S = 2.0


class Children:
    """The ``jointplay simulate`` processes of a server's downloads, so that they end with it.

    Each runs in the server's process group (Ctrl-C in its terminal reaches it too);
    :meth:`end`, called when the server stops (SIGTERM, SIGINT), stops those still running
    and refuses new ones.
    """

    def __init__(self) -> None:
        self._lock = threading.RLock()  # RLock: end() may run in a signal handler
        self._running: set[subprocess.Popen[str]] = set()
        self._ended = False

    @property
    def running(self) -> int:
        """How many run now."""
        with self._lock:
            return len(self._running)

    def run(self, args: list[str], *, cwd: Path, timeout: float) -> tuple[int, str]:
        """Run ``args`` in ``cwd`` to its end (its exit status and standard error).

        Raises:
            ConfigError: the server is stopping (:meth:`end` was called).
            subprocess.TimeoutExpired: it ran past ``timeout`` seconds (it is killed).
        """
        environment = {**os.environ, "MPLBACKEND": "Agg"}
        with self._lock:
            if self._ended:
                raise ConfigError(STOPPING)
            process = subprocess.Popen(
                args,
                cwd=cwd,
                env=environment,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                text=True,
            )
            self._running.add(process)
        try:
            _, stderr = process.communicate(timeout=timeout)
        except BaseException:
            process.kill()
            process.communicate()
            raise
        finally:
            with self._lock:
                self._running.discard(process)
        if self._ended:
            raise ConfigError(STOPPING)
        return process.returncode, stderr

    def end(self, wait: float = END_WAIT_S) -> None:
        """Stop every child (SIGTERM; SIGKILL for one still running after ``wait`` s) and
        refuse new ones. With ``wait=0`` it only signals (quick enough for a signal handler)."""
        with self._lock:
            self._ended = True
            running = list(self._running)
        for process in running:
            if process.poll() is None:
                process.terminate()
        if wait <= 0:
            return
        deadline = time.monotonic() + wait
        for process in running:
            try:
                process.wait(max(deadline - time.monotonic(), 0.01))
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


#: The error of a download that the server's stopping ended.
STOPPING = "the server is stopping: jointplay simulate was stopped; nothing to download"


def download(base: Base, settings: Settings, children: Children | None = None) -> bytes:
    """A ZIP archive of what ``jointplay simulate --config settings.toml --no-plots`` writes
    (summary.json, timeseries.csv, steps.csv) and that ``settings.toml``; the command runs
    as one of ``children`` (default: a set of its own).

    Raises:
        ConfigError: the command failed (its one-line message), or ``children`` were ended.
    """
    if settings.uniform() is None:
        raise ConfigError(
            "jointplay simulate takes one contact and friction for every joint, and these "
            "joints differ: give them the same contact and friction to download what the "
            "command writes"
        )
    text = settings_toml(base, settings)
    with tempfile.TemporaryDirectory(prefix="jointplay-explore-") as folder:
        work = Path(folder)
        (work / "settings.toml").write_text(text, encoding="utf-8")
        try:
            status, stderr = (children or Children()).run(
                [sys.executable, "-m", "jointplay", "simulate", *COMMAND],
                cwd=work,
                timeout=DOWNLOAD_TIMEOUT_S,
            )
        except subprocess.TimeoutExpired:
            raise ConfigError(
                f"jointplay simulate took longer than {DOWNLOAD_TIMEOUT_S:g} s; nothing to download"
            ) from None
        if status != 0:
            lines = [line for line in stderr.splitlines() if line.startswith("jointplay:")]
            raise ConfigError(lines[-1] if lines else f"jointplay simulate failed ({status})")
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("settings.toml", text)
            for item in sorted((work / "results").iterdir()):
                if item.is_file():
                    archive.write(item, item.name)
        return buffer.getvalue()
