"""An animation of the mechanism over one crank revolution, each pin's play magnified.

The pins of clearance joints move by micrometres in bearings of millimetres: drawn to scale,
nothing moves. The animation draws the links at their true positions and, at every
clearance joint, the bearing's clearance circle and the pin centre *magnified* by one stated
factor M: the circle has radius M·c about the bearing centre and the pin dot sits at the
bearing centre plus M·e, where c is the radial clearance and e = r_pin − r_bearing the
eccentricity (the ``ex_J``, ``ey_J`` columns of :meth:`SimulationResult.evaluate`). A faint
trace inside each circle is the pin's magnified orbit over the animated revolution.

The frames are taken on the continuous solution (cubic Hermite interpolation of the
positions between integrator steps, as :meth:`SimulationResult.evaluate` does) over one
revolution of the simulation — by default the last complete one, the steady cycle after the
start-up revolutions. :func:`write_animation` writes a GIF (Pillow, through matplotlib's
animation writers) or an MP4 (matplotlib's ffmpeg writer, which needs ``ffmpeg``).

Only drawing here: the geometry of each frame (:func:`mechanism_frames`) is read from a
:class:`~jointplay.dynamics.simulate.SimulationResult`; SI inside, millimetres on the axes.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError, SettingError
from jointplay.model.mechanism import GROUND, Mechanism, PrismaticJoint, RevoluteJoint
from jointplay.report._mpl import pyplot

if TYPE_CHECKING:
    from jointplay.dynamics.simulate import SimulationResult

FloatArray = NDArray[np.float64]

#: The file kinds :func:`write_animation` writes, by suffix, with matplotlib's writer name.
WRITERS = {".gif": "pillow", ".mp4": "ffmpeg"}

#: The default magnification draws the largest clearance circle with this radius, as a
#: fraction of the crank length (then rounded down to 1, 2 or 5 × 10^k): the pin's motion is
#: visible, yet small beside the links.
DISPLACEMENT_SHARE = 0.10

#: Bounds of the settings (beyond them a typo, or a file nobody can open).
MAX_FRAMES = 2000
MAX_FPS = 100
#: A GIF stores each frame's time in hundredths of a second, and browsers play frames of
#: less than 0.02 s at 0.1 s: a GIF runs at 50 fps at most.
MAX_GIF_FPS = 50
MAX_FIGURE_INCHES = 30.0
DPI_RANGE = (20, 400)
#: The animation's default size in pixels (width, height): at 960 px the paper four-bar's
#: ×500 clearance circles are about 20 px across, and the labels are legible.
DEFAULT_SIZE = (960, 640)
#: A size in pixels lays the drawing out on a figure this wide (inches), its dpi the width
#: over it: every size shows the same drawing, scaled (text included).
LAYOUT_WIDTH = 6.0
#: Each side of a size in pixels lies in this range; a width alone gets the default aspect.
SIZE_RANGE = (160, 4000)

_MM = 1e3  # the axes are in millimetres


@dataclass(frozen=True)
class Bearing:
    """A clearance joint over the frames.

    Attributes:
        joint: the joint's name.
        centre: bearing centre (the joint's point on ``link_a``) at each frame, m, (F, 2).
        eccentricity: pin centre − bearing centre at each frame, m, (F, 2).
        clearance: radial clearance c, m.
    """

    joint: str
    centre: FloatArray
    eccentricity: FloatArray
    clearance: float


@dataclass(frozen=True)
class MechanismFrames:
    """Where everything is at each frame (SI).

    Attributes:
        mechanism: the simulated mechanism.
        times: frame times, s, (F,).
        crank_deg: crank angle at each frame, degrees (unwrapped, as in the results).
        points: position of each joint point, keyed by (link, point), m, (F, 2); a ground
            point is constant.
        angles: angle of each moving link's frame, rad, (F,).
        bearings: the clearance joints.
        revolution: the animated revolution, counted from 1 over the whole simulated time
            (start-up revolutions included); ``None`` when less than one revolution was
            simulated and the frames span what there is.
        largest_displacement: largest |e| of each clearance joint over the animated span
            (frames and integrator steps), m.
    """

    mechanism: Mechanism
    times: FloatArray
    crank_deg: FloatArray
    points: Mapping[tuple[str, str], FloatArray]
    angles: Mapping[str, FloatArray]
    bearings: tuple[Bearing, ...]
    revolution: int | None
    largest_displacement: Mapping[str, float]

    @property
    def count(self) -> int:
        return int(self.times.shape[0])


@dataclass(frozen=True)
class AnimationInfo:
    """What :func:`write_animation` wrote.

    Attributes:
        path: the file.
        frames: number of frames.
        magnification: the factor M applied to pin displacements and clearance circles
            (1 without clearance joints).
        largest_displacement: largest pin displacement |e| of each clearance joint over the
            animated revolution, m (empty without clearance joints).
        size_bytes: size of the file, bytes.
        fps: frames per second.
        revolution: the animated revolution (see :attr:`MechanismFrames.revolution`).
    """

    path: Path
    frames: int
    magnification: float
    largest_displacement: dict[str, float]
    size_bytes: int
    fps: int
    revolution: int | None


def _whole(value: Any, name: str, low: int, high: int) -> int:
    """``value`` as a whole number in [low, high]; ``name`` says what it is (a
    :class:`~jointplay.errors.SettingError` template: ``{frames}`` names that setting)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise SettingError(name + " must be a whole number, got {got!r}", got=value)
    if not low <= int(value) <= high:
        raise SettingError(
            name + " must lie between {low} and {high}, got {got}", low=low, high=high, got=value
        )
    return int(value)


def _check_magnification(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise SettingError(
            "the magnification ({magnification}) must be a number, got {got!r}", got=value
        )
    if not (math.isfinite(value) and value > 0):
        raise SettingError(
            "the magnification ({magnification}) must be a finite number > 0 (e.g. 500), "
            "got {got!r}; leave it out to have one chosen",
            got=value,
        )
    return float(value)


def parse_size(value: Any) -> tuple[int, int]:
    """A size in pixels: ``"1280x720"`` (width x height), ``"1280"`` or ``1280`` (a width:
    the height follows :data:`DEFAULT_SIZE`'s aspect), or a ``(width, height)`` pair; each
    side a whole number in :data:`SIZE_RANGE`.

    Raises:
        SettingError: naming the setting ``{size}`` and what it must be.
    """
    low, high = SIZE_RANGE
    bad = SettingError(
        "the animation size ({size}) must be WIDTHxHEIGHT or a WIDTH in pixels, each side a "
        "whole number from {low} to {high} (e.g. 1280x720), got {got!r}",
        low=low,
        high=high,
        got=value,
    )
    if isinstance(value, str):
        parts = value.strip().lower().replace("×", "x").split("x")
        if not (1 <= len(parts) <= 2 and all(p.strip().isdigit() for p in parts)):
            raise bad
        sides = [int(p) for p in parts]
    elif isinstance(value, int | np.integer) and not isinstance(value, bool):
        sides = [int(value)]
    elif isinstance(value, tuple | list) and len(value) == 2:
        if not all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in value):
            raise bad
        sides = [int(v) for v in value]
    else:
        raise bad
    if len(sides) == 1:
        sides.append(round(sides[0] * DEFAULT_SIZE[1] / DEFAULT_SIZE[0]))
    if not all(low <= side <= high for side in sides):
        raise bad
    return sides[0], sides[1]


def size_layout(size: tuple[int, int]) -> tuple[tuple[float, float], float]:
    """The figure size (inches) and dpi that draw exactly ``size`` pixels: the layout
    :data:`LAYOUT_WIDTH` inches wide, scaled."""
    width, height = size
    dpi = width / LAYOUT_WIDTH
    return (LAYOUT_WIDTH, height / dpi), dpi


def animation_writer(path: Path | str) -> str:
    """The matplotlib writer for ``path`` (by its suffix), or a ConfigError saying what to do.

    Raises:
        ConfigError: the suffix is neither ``.gif`` nor ``.mp4``, or ``.mp4`` is asked for
            and ``ffmpeg`` is not installed.
    """
    suffix = Path(path).suffix.lower()
    if suffix not in WRITERS:
        raise ConfigError(
            f"the animation file {str(path)!r} must end in .gif or .mp4 (got "
            f"{suffix or 'no suffix'})"
        )
    name = WRITERS[suffix]
    if name == "ffmpeg":
        from matplotlib import animation

        if not animation.writers.is_available("ffmpeg"):
            raise ConfigError(
                "writing an MP4 needs ffmpeg, which is not installed (or not on PATH): "
                "install it (e.g. 'apt install ffmpeg' or 'conda install ffmpeg') or write "
                "a .gif instead"
            )
    return name


def check_animation_settings(
    path: Path | str,
    *,
    magnification: float | None = None,
    fps: int = 20,
    frames: int = 72,
    figure_size: tuple[float, float] | None = None,
    dpi: int | None = None,
    size: Any = None,
) -> str:
    """Check the settings of :func:`write_animation` before any work; return the writer's
    name (``"pillow"`` or ``"ffmpeg"``).

    Raises:
        ConfigError: naming the setting at fault and the range it must lie in.
    """
    name = animation_writer(path)
    if magnification is not None:
        _check_magnification(magnification)
    _whole(fps, "frames per second ({fps})", 1, MAX_GIF_FPS if name == "pillow" else MAX_FPS)
    _whole(frames, "the number of frames ({frames})", 2, MAX_FRAMES)
    if size is not None:
        parse_size(size)
    if figure_size is not None:
        _figure_size(figure_size)
    if dpi is not None:
        _whole(dpi, "dpi", *DPI_RANGE)
    return name


def default_magnification(clearance: float, crank_length: float) -> float:
    """M such that the largest clearance circle's radius M·c is about
    :data:`DISPLACEMENT_SHARE` of the crank length, rounded down to 1, 2 or 5 × 10^k, and
    never below 1.

    The clearance, not the largest eccentricity, sets the factor: in contact the eccentricity
    is c plus the penetration, which depends on the contact law, and animations of several
    laws (the paper's methods) should share one scale.

    Args:
        clearance: the largest radial clearance, m (0: no magnification, M = 1).
        crank_length: m.
    """
    if not clearance > 0:
        return 1.0
    wanted = DISPLACEMENT_SHARE * crank_length / clearance
    if wanted <= 1.0:
        return 1.0
    decade = 10.0 ** math.floor(math.log10(wanted))
    return max(step * decade for step in (1.0, 2.0, 5.0) if step * decade <= wanted * (1 + 1e-12))


def crank_length(mechanism: Mechanism) -> float:
    """Largest distance between two named points of the crank, m."""
    points = list(mechanism.link(mechanism.driver.link).points.values())
    return max((math.dist(p, q) for p in points for q in points), default=0.0)


def _frame_times(
    result: SimulationResult, frames: int, revolution: int | None
) -> tuple[FloatArray, int | None]:
    """The frame times and the revolution they cover."""
    period = result.mechanism.driver.period
    t_last = float(result.t[-1])
    complete = math.floor(t_last / period * (1.0 + 1e-9))
    if revolution is None:
        if complete < 1:  # less than one revolution simulated: span what there is
            return np.linspace(0.0, t_last, frames), None
        revolution = complete
    elif complete < 1 or not 1 <= revolution <= complete:
        raise ConfigError(
            f"revolution {revolution} is not among the simulated ones: "
            + (
                f"1 to {complete} ran completely (start-up revolutions included)"
                if complete
                else "less than one revolution was simulated"
            )
        )
    start = (revolution - 1) * period
    # The end is left out: the last frame leads back to the first, so the loop is seamless.
    return start + period * np.arange(frames) / frames, revolution


def _positions(result: SimulationResult, times: FloatArray) -> FloatArray:
    """The coordinates q at ``times`` (F, n): the interpolation of
    :meth:`SimulationResult.evaluate` (cubic Hermite of q with q̇ between accepted steps)."""
    from jointplay.dynamics.simulate import hermite

    n = result.system.n_coordinates
    return hermite(result.t, result.y[:, :n], result.y[:, n : 2 * n], times)


def mechanism_frames(
    result: SimulationResult, *, frames: int = 72, revolution: int | None = None
) -> MechanismFrames:
    """The geometry of ``frames`` evenly spaced instants of one revolution of ``result``.

    A joint point s (in its link's frame, relative to the centre of mass) of link k lies at
    r = r_k + R(φ_k) s. The eccentricity of a clearance joint is e = r_pin − r_bearing, the
    pin on the joint's ``link_b``, the bearing on its ``link_a``.

    Args:
        result: a simulation (a failed one too: its frames cover what was simulated).
        frames: number of frames (2 to :data:`MAX_FRAMES`).
        revolution: which revolution, counted from 1 over the simulated time, start-up
            revolutions included (default: the last complete one).

    Raises:
        ConfigError: a setting is out of range or the revolution was not simulated.
    """
    frames = _whole(frames, "the number of frames ({frames})", 2, MAX_FRAMES)
    if revolution is not None:
        revolution = _whole(revolution, "revolution", 1, 10**9)
    if result.t.shape[0] < 2:
        raise ConfigError(
            f"the simulation stopped at its initial state ({result.message}); nothing to animate"
        )
    times, revolution = _frame_times(result, frames, revolution)
    q = _positions(result, times)
    mechanism = result.mechanism
    flat = result.system.flat
    count = times.shape[0]
    angles: dict[str, FloatArray] = {}
    points: dict[tuple[str, str], FloatArray] = {}
    for joint in mechanism.joints:
        for body, name in ((joint.link_a, joint.point_a), (joint.link_b, joint.point_b)):
            if (body, name) in points:
                continue
            if body == GROUND:
                points[body, name] = np.tile(mechanism.ground.point(name), (count, 1))
                continue
            link = mechanism.link(body)
            k = flat.body_index(body)
            phi = q[:, 3 * k + 2]
            angles[body] = phi
            sx, sy = np.subtract(link.point(name), link.com)
            points[body, name] = np.column_stack(
                [
                    q[:, 3 * k] + np.cos(phi) * sx - np.sin(phi) * sy,
                    q[:, 3 * k + 1] + np.sin(phi) * sx + np.cos(phi) * sy,
                ]
            )
    crank = flat.body_index(mechanism.driver.link)
    bearings = []
    largest: dict[str, float] = {}
    steps = result.steps
    in_span = steps["t"].between(times[0], times[-1] + (times[-1] - times[0]) / max(count - 1, 1))
    for clearance in result.system.clearances:
        joint = mechanism.joint(clearance.joint)
        centre = points[joint.link_a, joint.point_a]
        eccentricity = points[joint.link_b, joint.point_b] - centre
        bearings.append(Bearing(clearance.joint, centre, eccentricity, clearance.clearance))
        stepped = steps.loc[in_span, f"e_{clearance.joint}"].to_numpy()
        largest[clearance.joint] = float(
            max(np.max(np.hypot(*eccentricity.T)), np.max(stepped, initial=0.0))
        )
    return MechanismFrames(
        mechanism=mechanism,
        times=times,
        crank_deg=np.degrees(q[:, 3 * crank + 2]),
        points=points,
        angles=angles,
        bearings=tuple(bearings),
        revolution=revolution,
        largest_displacement=largest,
    )


class MechanismAnimation:
    """The figure of a :class:`MechanismFrames` and its artists, moved by :meth:`update`.

    Attributes:
        figure: the matplotlib figure.
        magnification: M.
        links: a line (bar through its joint points) or a polygon (a slider block) per link.
        bearings: the magnified clearance circle of each clearance joint (axes in mm).
        pins: the pin-centre dot of each clearance joint (axes in mm).
        orbits: the magnified orbit of each pin over the animated span, about the bearing.
        clock: the text giving the crank angle and time.
    """

    def __init__(
        self,
        frames: MechanismFrames,
        magnification: float,
        *,
        figure_size: tuple[float, float] = (6.0, 4.0),
        dpi: float = 80,
        title: str | None = None,
    ) -> None:
        from matplotlib.patches import Circle, Polygon

        plt = pyplot()
        self.frames = frames
        self.magnification = magnification
        mechanism = frames.mechanism
        scale = crank_length(mechanism) * _MM or 1.0  # the size of the symbols, mm
        self._block = (0.5 * scale, 0.3 * scale)  # slider block length, height, mm
        self.figure, ax = plt.subplots(figsize=figure_size, dpi=dpi)
        self.axes = ax
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        ax.set_xlabel("x (mm)", fontsize=8)
        ax.set_ylabel("y (mm)", fontsize=8)

        # Which points each link has in joints (in joint order), and which links are sliders.
        self._link_points: dict[str, list[str]] = {}
        for joint in mechanism.joints:
            for body, name in ((joint.link_a, joint.point_a), (joint.link_b, joint.point_b)):
                if body != GROUND and name not in self._link_points.setdefault(body, []):
                    self._link_points[body].append(name)
        self.links: dict[str, Any] = {}
        for number, link in enumerate(mechanism.links):
            colour = f"C{number % 10}"
            names = self._link_points.get(link.name, [])
            if len(names) >= 2:
                (line,) = ax.plot(
                    [], [], color=colour, lw=4, solid_capstyle="round", alpha=0.85, zorder=2
                )
                self.links[link.name] = line
            elif names:
                block = Polygon(np.zeros((4, 2)), closed=True, fc=colour, ec="0.2", alpha=0.85)
                block.set_zorder(2)
                ax.add_patch(block)
                self.links[link.name] = block

        self._draw_ground(ax, scale)

        clearance_joints = {b.joint for b in frames.bearings}
        ideal = [
            j
            for j in mechanism.joints
            if isinstance(j, RevoluteJoint) and j.name not in clearance_joints
        ]
        self._ideal = ideal
        (self._ideal_pins,) = ax.plot(
            [], [], "o", ms=4.5, mfc="white", mec="0.15", mew=1.0, ls="none", zorder=4
        )
        self.bearings: dict[str, Any] = {}
        self.pins: dict[str, Any] = {}
        self.orbits: dict[str, Any] = {}
        for bearing in frames.bearings:
            circle = Circle(
                (0.0, 0.0), magnification * bearing.clearance * _MM, fill=False, ec="0.1", lw=1.0
            )
            circle.set_zorder(3)
            ax.add_patch(circle)
            self.bearings[bearing.joint] = circle
            (self.orbits[bearing.joint],) = ax.plot([], [], color="C3", lw=0.6, alpha=0.5, zorder=3)
            (self.pins[bearing.joint],) = ax.plot(
                [], [], "o", ms=4.0, color="C3", mec="0.1", mew=0.6, zorder=5
            )

        self._limits(ax, scale)
        if frames.bearings:
            factor = f"{magnification:g}"
            note = f"pin displacement in its bearing × {factor}, clearance circles × {factor}"
            if any(
                np.max(np.hypot(*b.eccentricity.T)) > b.clearance for b in frames.bearings
            ):  # e = c + penetration in contact
                note += "\na pin beyond its circle presses into the bearing wall (penetration)"
        else:
            note = "ideal joints: no pin displacement"
        span = (
            f"revolution {frames.revolution}"
            if frames.revolution is not None
            else f"the first {frames.times[-1]:.3g} s"
        )
        ax.set_title(f"{title or f'{mechanism.name}: {span}'}\n{note}", fontsize=8)
        self.clock = ax.text(
            0.01, 0.01, "", transform=ax.transAxes, fontsize=8, va="bottom", family="monospace"
        )
        self.figure.tight_layout()
        self.update(0)

    def _draw_ground(self, ax: Any, scale: float) -> None:
        """Hatched ground symbols: a triangle under each ground pivot, a strip along each
        ground slide (static)."""
        from matplotlib.patches import Polygon

        mechanism = self.frames.mechanism
        size = 0.12 * scale
        for joint in mechanism.joints:
            if GROUND not in (joint.link_a, joint.link_b):
                continue
            point = joint.point_a if joint.link_a == GROUND else joint.point_b
            x, y = np.multiply(mechanism.ground.point(point), _MM)
            if isinstance(joint, RevoluteJoint):
                ax.add_patch(
                    Polygon(
                        [(x, y), (x - size, y - 1.6 * size), (x + size, y - 1.6 * size)],
                        closed=True,
                        fc="0.85",
                        ec="0.3",
                        lw=0.8,
                        zorder=1,
                    )
                )
                ax.add_patch(
                    Polygon(
                        [
                            (x - 1.6 * size, y - 1.6 * size),
                            (x + 1.6 * size, y - 1.6 * size),
                            (x + 1.6 * size, y - 2.2 * size),
                            (x - 1.6 * size, y - 2.2 * size),
                        ],
                        closed=True,
                        fc="none",
                        ec="0.3",
                        hatch="////",
                        lw=0.0,
                        zorder=1,
                    )
                )
            elif isinstance(joint, PrismaticJoint):
                slider = self.frames.points[joint.link_b, joint.point_b] * _MM
                axis = np.array([math.cos(joint.axis_angle), math.sin(joint.axis_angle)])
                normal = np.array([-axis[1], axis[0]])
                travel = (slider - (x, y)) @ axis
                ends = (travel.min() - self._block[0], travel.max() + self._block[0])
                below = -0.5 * self._block[1]
                corners = [
                    (x, y) + ends[0] * axis + below * normal,
                    (x, y) + ends[1] * axis + below * normal,
                    (x, y) + ends[1] * axis + (below - 0.6 * size) * normal,
                    (x, y) + ends[0] * axis + (below - 0.6 * size) * normal,
                ]
                ax.add_patch(
                    Polygon(corners, closed=True, fc="none", ec="0.3", hatch="////", lw=0.0)
                )
                ax.plot(*np.transpose(corners[:2]), color="0.3", lw=1.0, zorder=1)

    def _limits(self, ax: Any, scale: float) -> None:
        everything = np.concatenate([p * _MM for p in self.frames.points.values()])
        low, high = everything.min(axis=0), everything.max(axis=0)
        pad = 0.45 * scale
        ax.set_xlim(low[0] - pad, high[0] + pad)
        ax.set_ylim(low[1] - pad, high[1] + 0.8 * pad)

    def update(self, i: int) -> list[Any]:
        """Move every artist to frame ``i``; return the artists that changed."""
        frames = self.frames
        m = self.magnification
        changed: list[Any] = []
        for name, artist in self.links.items():
            names = self._link_points[name]
            xy = np.array([frames.points[name, p][i] for p in names]) * _MM
            if len(names) >= 2:
                if len(names) >= 3:
                    xy = np.vstack([xy, xy[:1]])
                artist.set_data(xy[:, 0], xy[:, 1])
            else:
                phi = frames.angles[name][i]  # the block turns with its link
                along = np.array([math.cos(phi), math.sin(phi)]) * 0.5 * self._block[0]
                across = np.array([-math.sin(phi), math.cos(phi)]) * 0.5 * self._block[1]
                centre = xy[0]
                artist.set_xy(
                    [
                        centre - along - across,
                        centre + along - across,
                        centre + along + across,
                        centre - along + across,
                    ]
                )
            changed.append(artist)
        if self._ideal:
            ideal = np.array([frames.points[j.link_a, j.point_a][i] for j in self._ideal]) * _MM
            self._ideal_pins.set_data(ideal[:, 0], ideal[:, 1])
            changed.append(self._ideal_pins)
        for bearing in frames.bearings:
            centre = bearing.centre[i] * _MM
            self.bearings[bearing.joint].set_center((float(centre[0]), float(centre[1])))
            pin = centre + m * bearing.eccentricity[i] * _MM
            self.pins[bearing.joint].set_data([pin[0]], [pin[1]])
            orbit = centre + m * bearing.eccentricity * _MM
            self.orbits[bearing.joint].set_data(orbit[:, 0], orbit[:, 1])
            changed += [self.bearings[bearing.joint], self.pins[bearing.joint]]
            changed.append(self.orbits[bearing.joint])
        self.clock.set_text(
            f"crank {frames.crank_deg[i] % 360.0:5.1f}°   t = {frames.times[i]:.4f} s"
        )
        changed.append(self.clock)
        return changed

    def images(self) -> Iterator[NDArray[np.uint8]]:
        """Each frame as an RGB array (height, width, 3), drawn by blitting: the still parts
        (axes, ground, title) are rendered once, then only the moving artists per frame."""
        canvas = self.figure.canvas
        self.update(0)
        moving = sorted(self.update(0), key=lambda artist: artist.get_zorder())
        for artist in moving:
            artist.set_animated(True)
        try:
            canvas.draw()
            background = canvas.copy_from_bbox(self.figure.bbox)
            for i in range(self.frames.count):
                canvas.restore_region(background)
                for artist in sorted(self.update(i), key=lambda artist: artist.get_zorder()):
                    self.figure.draw_artist(artist)
                yield np.array(canvas.buffer_rgba())[..., :3]
        finally:
            for artist in moving:
                artist.set_animated(False)

    def close(self) -> None:
        pyplot().close(self.figure)


def write_animation(
    result: SimulationResult,
    path: Path,
    *,
    magnification: float | None = None,
    fps: int = 20,
    frames: int = 72,
    revolution: int | None = None,
    size: Any = None,
    figure_size: tuple[float, float] | None = None,
    dpi: int | None = None,
    title: str | None = None,
) -> AnimationInfo:
    """Write an animation of ``result`` over one revolution to ``path`` (.gif or .mp4).

    Args:
        result: the simulation.
        path: the file to write; its suffix picks the format (``.gif``: Pillow; ``.mp4``:
            ffmpeg, which must be installed).
        magnification: the factor M on the pin displacements and clearance circles (> 0;
            default :func:`default_magnification` of the largest clearance). Stated in
            every frame.
        fps: frames per second (1 to :data:`MAX_FPS`; for a GIF, up to
            :data:`MAX_GIF_FPS`, and each frame lasts a whole number of hundredths of a
            second: 12 fps plays at 12.5).
        frames: number of frames over the revolution (2 to :data:`MAX_FRAMES`).
        revolution: the revolution to animate, counted from 1 over the simulated time,
            start-up revolutions included (default: the last complete one, the steady cycle).
        size: width and height in pixels (``"1280x720"``, a width ``1280`` with the default
            aspect, or a pair; :func:`parse_size`); default :data:`DEFAULT_SIZE` (960 x 640)
            unless ``figure_size`` or ``dpi`` is given.
        figure_size: width and height, inches (instead of ``size``; default 6 x 4).
        dpi: pixels per inch (instead of ``size``; default 160 with ``figure_size``).
        title: the title of every frame (default: the mechanism's name and the revolution).

    Returns:
        What was written: file, frame count, magnification, largest pin displacement per
        clearance joint (m), size in bytes.

    Raises:
        ConfigError: a setting is out of range, the suffix is not .gif or .mp4, or an MP4 is
            asked for without ffmpeg.
    """
    path = Path(path)
    writer_name = check_animation_settings(
        path,
        magnification=magnification,
        fps=fps,
        frames=frames,
        figure_size=figure_size,
        dpi=dpi,
        size=size,
    )
    if magnification is not None:
        magnification = float(magnification)
    inches: tuple[float, float]
    pixels_per_inch: float
    if size is not None or (figure_size is None and dpi is None):
        inches, pixels_per_inch = size_layout(DEFAULT_SIZE if size is None else parse_size(size))
    else:
        inches = _figure_size((6.0, 4.0) if figure_size is None else figure_size)
        pixels_per_inch = 160 if dpi is None else dpi
    geometry = mechanism_frames(result, frames=frames, revolution=revolution)
    if magnification is None:
        magnification = (
            default_magnification(
                max(b.clearance for b in geometry.bearings), crank_length(result.mechanism)
            )
            if geometry.bearings
            else 1.0
        )
    drawing = MechanismAnimation(
        geometry, magnification, figure_size=inches, dpi=pixels_per_inch, title=title
    )
    try:
        if writer_name == "pillow":
            _write_gif(drawing, path, fps)
        else:
            _write_movie(drawing, path, writer_name, fps, pixels_per_inch)
    finally:
        drawing.close()
    return AnimationInfo(
        path=path,
        frames=geometry.count,
        magnification=magnification,
        largest_displacement=dict(geometry.largest_displacement),
        size_bytes=path.stat().st_size,
        fps=fps,
        revolution=geometry.revolution,
    )


#: Colours of a GIF's one palette (shared by all frames, so that each frame stores only
#: what changed): the flat colours of the drawing and their anti-aliased edges.
GIF_COLOURS = 128


def _write_gif(drawing: MechanismAnimation, path: Path, fps: int) -> None:
    """Blitted frames quantised to the first frame's palette, written by Pillow (the
    library behind matplotlib's GIF writer) looping forever."""
    from PIL import Image

    images = [Image.fromarray(rgb) for rgb in drawing.images()]
    first = images[0].quantize(
        colors=GIF_COLOURS, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE
    )
    rest = [image.quantize(palette=first, dither=Image.Dither.NONE) for image in images[1:]]
    first.save(
        path,
        format="GIF",
        save_all=True,
        append_images=rest,
        duration=10 * round(100 / fps),  # ms, a whole number of hundredths of a second
        loop=0,
    )


def _write_movie(
    drawing: MechanismAnimation, path: Path, writer_name: str, fps: int, dpi: float
) -> None:
    """Every frame drawn in full and piped to matplotlib's movie writer (ffmpeg)."""
    from matplotlib import animation

    writer = animation.writers[writer_name](fps=fps)
    with writer.saving(drawing.figure, str(path), dpi):
        for i in range(drawing.frames.count):
            drawing.update(i)
            writer.grab_frame()


def _figure_size(value: Any) -> tuple[float, float]:
    try:
        width, height = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigError(f"figure_size must be (width, height) in inches, got {value!r}") from None
    if not all(math.isfinite(v) and 0 < v <= MAX_FIGURE_INCHES for v in (width, height)):
        raise ConfigError(
            f"figure_size must be two sizes in inches between 0 and {MAX_FIGURE_INCHES:g}, "
            f"got {value!r}"
        )
    return width, height
