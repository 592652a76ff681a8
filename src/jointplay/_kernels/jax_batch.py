"""The batch kernel on JAX (GPU, or JAX's CPU backend): many samples of one mechanism at once.

:func:`run_batch` has the signature and semantics of the batch-kernel contract shared with
the Numba backend (:mod:`jointplay._kernels.batch`): every lane (sample) has its own packed
model row ``rpar`` and initial state ``y0``, all lanes share the integer structure ``ipar``;
each lane is integrated from t = 0 to its ``t_end`` without dense output, and the result is
its peaks over [t_settle, t_end] (QUANTITY ORDER: ω_b, α_b, F_j, torque), its steady-cycle
statistics (mean and RMS of ω_b, largest penetration of each clearance joint), its status
and counters. The equations of motion are :mod:`jointplay._kernels.jax.eom`, the integrators
(explicit Dormand–Prince 5(4), implicit Radau IIA 5; step control and the PEAK RULE) are
:mod:`jointplay._kernels.jax.integrate`.

Execution: float64 throughout (``jax_enable_x64`` switched on only while a batch is traced
and run); the lanes are cut into chunks of a fixed size (at most ``chunk_size``, default
:data:`DEFAULT_CHUNK` = 200 000: the throughput of one batched loop falls beyond that) and the
last chunk is padded with copies of the first lane, so that one compilation serves every
chunk; batches smaller than a chunk are padded to the next :func:`padded_size` bucket, so
that nearby batch sizes share a compilation too. Compiled programs are kept in JAX's
persistent compilation cache, in ``$JOINTPLAY_JAX_CACHE`` (``off`` disables it) or else
``jointplay/jax`` under the user's cache folder (``$XDG_CACHE_HOME`` or ``~/.cache``), unless
the program has set a cache folder of its own; the traced programs are kept there too
(``exported/``, :func:`_compile`), so that a later process skips tracing. The folder must be
private (:func:`private_folder`: this user's, writable by no one else; else it is not used),
kept programs are written by exclusive create and renamed into place, and read back only
when they are this user's regular files whose content matches the digest written with them.

JAX is imported by this module only, and only when a batch is run (``import jointplay``
never imports it); without JAX, :func:`run_batch` raises a
:class:`~jointplay.errors.ConfigError` saying how to install it (``jointplay[gpu]``).
"""

from __future__ import annotations

import hashlib
import os
import stat
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from jointplay._kernels.integrators import lane_methods
from jointplay._kernels.lanes.contract import BatchKernelOutput  # one result type for every backend
from jointplay.errors import ConfigError

__all__ = [
    "DEFAULT_CHUNK",
    "BatchKernelOutput",
    "cache_dir",
    "padded_size",
    "run_batch",
]

#: Default (and largest useful) number of lanes per compiled chunk.
DEFAULT_CHUNK = 200_000
#: The environment variable naming the persistent compilation cache folder (``off``: none).
CACHE_ENV = "JOINTPLAY_JAX_CACHE"
#: The methods of :func:`run_batch`: those of the integrators the JAX lanes have.
METHODS = lane_methods("jax")


def _import_jax() -> Any:
    try:
        import jax
    except ImportError as exc:  # the optional extra is not installed
        raise ConfigError(
            "the GPU batch backend needs JAX: pip install 'jointplay[gpu]' (or pip install "
            "'jax[cuda12]' for NVIDIA GPUs); its CPU backend runs without a GPU"
        ) from exc
    return jax


def _x64(jax: Any) -> Any:
    """A context in which JAX computes in float64 (``jax.enable_x64``; before JAX 0.5,
    ``jax.experimental.enable_x64``)."""
    scoped = getattr(jax, "enable_x64", None)
    if scoped is not None:
        return scoped(True)
    from jax import experimental

    return experimental.enable_x64()  # type: ignore[attr-defined]


def cache_dir() -> Path | None:
    """The persistent compilation cache folder (module docstring), ``None`` when disabled."""
    value = os.environ.get(CACHE_ENV)
    if value is not None:
        return None if value.strip().lower() in ("", "off", "0", "none") else Path(value)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "jointplay" / "jax"


_configured = False


def _configure(jax: Any) -> None:
    """Switch on the persistent compilation cache once, unless the program chose its own."""
    global _configured
    if _configured:
        return
    _configured = True
    folder = cache_dir()
    if folder is None or jax.config.jax_compilation_cache_dir or not private_folder(folder):
        return  # no usable cache folder only costs compilation time
    jax.config.update("jax_compilation_cache_dir", str(folder))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)


def private_folder(folder: Path) -> bool:
    """Make ``folder`` (and its parents) if needed and say whether it is private to this user:
    a real folder (not a symbolic link), owned by this user, that no one else can write
    (it is made 0700, and a folder of this user's that others could write is made so). A
    cache folder that others can write could hand this process a program to run; it is not
    used."""
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        info = os.lstat(folder)
        if not stat.S_ISDIR(info.st_mode) or info.st_uid != os.getuid():
            return False
        if info.st_mode & 0o077:
            os.chmod(folder, 0o700)
    except OSError:
        return False
    return True


#: Fewest lanes per chunk of the explicit method on a GPU. Measured on one H100 (one
#: revolution): 1 000 lanes ran in 20.9 s after a 68 s compilation, 10 000 in 1.2 s after
#: 17 s: small explicit batches take a slow path there, so they are padded up to this (copies
#: of a lane). The implicit method is not padded: its 1 000 lanes ran in 7.5 s as they are
#: and in 28 s padded to 16 384 (its cost grows with the lanes).
GPU_MIN_LANES = 16_384


def padded_size(n: int, chunk_size: int, minimum: int = 1) -> int:
    """Lanes per compiled chunk for a batch of ``n``: ``chunk_size`` when the batch fills at
    least one chunk; otherwise ``n`` rounded up to a power of two (below 1024) or to a
    multiple of 1024, so that nearby batch sizes share one compilation, and at least
    ``minimum`` (never above ``chunk_size``)."""
    n = max(n, min(minimum, chunk_size))
    if n >= chunk_size:
        return chunk_size
    if n <= 1024:
        return min(chunk_size, max(1, 1 << (n - 1).bit_length()))
    return min(chunk_size, -(-n // 1024) * 1024)


_compiled: dict[Any, Any] = {}
#: Compiled executables by (layout, method, lanes per chunk, R, S), for this process.
_executables: dict[Any, Any] = {}


def _batch_function(layout: Any, method: str) -> Any:
    """The jitted, vmapped integrator for one layout and method (built once)."""
    key = (layout, method)
    if key not in _compiled:
        import jax

        from jointplay._kernels.jax.eom import JaxModel
        from jointplay._kernels.jax.integrate import batch_runner

        _compiled[key] = jax.jit(batch_runner(JaxModel(layout), method))
    return _compiled[key]


def _compile(jax: Any, layout: Any, method: str, args: tuple[Any, ...]) -> Any:
    """The compiled batch function for ``args``'s shapes.

    Tracing and lowering the kernel takes 1.3 s on this machine's CPU (1.2–1.9 s measured on
    an H100), every process, even when the persistent cache then holds the compiled
    program. So the lowered program is also kept, serialized with :mod:`jax.export`, beside
    that cache (:func:`_exported_path`); a later process reads it back (~0.1 s) and compiles
    it, from the persistent cache when it is there. Without a cache folder, or without
    ``flatbuffers`` (which serialization needs), the kernel is traced every time.
    """
    path = _exported_path(jax, layout, method, args)
    exported = None if path is None else _read_exported(jax, path)
    if exported is None:
        function = _batch_function(layout, method)
        if path is None:
            return function.lower(*args).compile()
        from jax import export

        try:
            exported = export.export(function)(*args)
        except Exception:  # e.g. a library call jax.export cannot serialize on this platform
            return function.lower(*args).compile()
        _write_exported(exported, path)
    return jax.jit(exported.call).lower(*args).compile()


def _exported_path(jax: Any, layout: Any, method: str, args: tuple[Any, ...]) -> Path | None:
    """Where the serialized program for these inputs lives (``None``: not kept). Its name is
    a digest of everything the program depends on: the JAX version and platform, the
    method, the layout, the argument shapes and the source of every kernel module (so an
    edited kernel is traced afresh)."""
    folder = cache_dir()
    if folder is None or not private_folder(folder / "exported"):
        return None
    digest = hashlib.sha256()
    shapes = [(np.shape(a), np.asarray(a).dtype.str) for a in args]
    for part in (jax.__version__, jax.default_backend(), method, layout, shapes):
        digest.update(repr(part).encode())
    for source in sorted(Path(__file__).parent.rglob("*.py")):
        digest.update(source.read_bytes())
    return folder / "exported" / f"{digest.hexdigest()}.bin"


#: The first bytes of a kept program: a tag, then the SHA-256 of the program that follows.
_EXPORTED_TAG = b"jointplay-exported-1\n"


def _read_exported(jax: Any, path: Path) -> Any:
    """The deserialized program at ``path``; ``None`` when absent, unreadable, not a regular
    file of this user's that only this user can write (a symbolic link is not followed), or
    not what was written (its digest does not match)."""
    from jax import export

    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return None
    with os.fdopen(descriptor, "rb") as handle:
        info = os.fstat(descriptor)
        if not stat.S_ISREG(info.st_mode) or info.st_uid != os.getuid() or info.st_mode & 0o022:
            return None
        data = handle.read()
    head, digest, blob = (
        data[: len(_EXPORTED_TAG)],
        data[len(_EXPORTED_TAG) : len(_EXPORTED_TAG) + 32],
        data[len(_EXPORTED_TAG) + 32 :],
    )
    if head != _EXPORTED_TAG or hashlib.sha256(blob).digest() != digest:
        return None
    try:
        return export.deserialize(bytearray(blob))
    except Exception:  # damaged or foreign: trace afresh (and replace it)
        return None


def _write_exported(exported: Any, path: Path) -> None:
    """Serialize ``exported`` to ``path``: written to a fresh file made by exclusive create
    (a random name, mode 0600, never through a symbolic link), then renamed into place;
    failing to only costs tracing later."""
    try:
        blob = exported.serialize()
        descriptor, name = tempfile.mkstemp(prefix=".", suffix=".tmp", dir=path.parent)
        try:
            with os.fdopen(descriptor, "wb") as handle:
                handle.write(_EXPORTED_TAG + hashlib.sha256(blob).digest() + bytes(blob))
            os.replace(name, path)
        except BaseException:
            os.unlink(name)
            raise
    except (ImportError, OSError):  # no flatbuffers, or an unwritable folder
        return


def _check(
    ipar: np.ndarray, rpar: np.ndarray, y0: np.ndarray, t_settle: np.ndarray,
    t_end: np.ndarray, max_step: np.ndarray, rtol: float, atol: np.ndarray, max_steps: int,
    method: str,
) -> None:  # fmt: skip
    n = rpar.shape[0]
    if method not in METHODS:
        raise ConfigError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if rpar.ndim != 2 or y0.ndim != 2 or y0.shape[0] != n:
        raise ConfigError(
            f"rpar and y0 must be (lanes, R) and (lanes, S) arrays with the same number of "
            f"lanes, got shapes {rpar.shape} and {y0.shape}"
        )
    for name, values in (("t_settle", t_settle), ("t_end", t_end), ("max_step", max_step)):
        if values.shape != (n,):
            raise ConfigError(
                f"{name} must have one entry per lane ({n}), got shape {values.shape}"
            )
        if not np.all(np.isfinite(values)):
            raise ConfigError(f"{name} must be finite in every lane")
    if not (np.all(t_end > 0) and np.all(t_settle >= 0) and np.all(t_settle <= t_end)):
        raise ConfigError("every lane needs 0 <= t_settle <= t_end and t_end > 0 s")
    if not np.all(max_step > 0):
        raise ConfigError("max_step must be > 0 s in every lane")
    if atol.shape != (y0.shape[1],) or not np.all(atol > 0):
        raise ConfigError(f"atol must hold one positive entry per state component ({y0.shape[1]})")
    if not (0 < rtol < 0.1):
        raise ConfigError(f"rtol must lie in (0, 0.1), got {rtol}")
    if max_steps < 1:
        raise ConfigError(f"max_steps must be >= 1, got {max_steps}")


def run_batch(
    ipar: np.ndarray,
    rpar: np.ndarray,
    y0: np.ndarray,
    t_settle: np.ndarray,
    t_end: np.ndarray,
    max_step: np.ndarray,
    rtol: float,
    atol: np.ndarray,
    max_steps: int,
    method: str,
    *,
    chunk_size: int | None = None,
    timings: dict[str, float] | None = None,
) -> BatchKernelOutput:
    """Integrate every lane on JAX's default device (the batch contract; module docstring).

    Args:
        ipar: (I,) int64, the integer structure shared by every lane (:func:`eom.pack`).
        rpar: (n, R) float64, each lane's packed model.
        y0: (n, S) float64, each lane's initial state at t = 0.
        t_settle, t_end: (n,) start and end of each lane's analysed window, s.
        max_step: (n,) largest step of each lane, s.
        rtol: relative tolerance; atol: (S,) absolute tolerances (only the first
            2·n_coordinates enter the error norm).
        max_steps: accepted steps after which a lane stops unfinished.
        method: ``"explicit"`` (Dormand–Prince 5(4)) or ``"implicit"`` (Radau IIA 5).
        chunk_size: lanes per compiled chunk (default :data:`DEFAULT_CHUNK`).
        timings: if given, receives ``compile_s`` (tracing and compiling, or loading from the
            persistent cache; 0 when this process had compiled it already), ``run_s`` and
            ``lanes`` (the lanes that ran in ``run_s``, padding included).

    Returns:
        A :class:`BatchKernelOutput` of NumPy arrays, one row per lane.

    Raises:
        ConfigError: JAX is missing, an input is malformed, or the mechanism uses a law the
            JAX port does not know.
    """
    jax = _import_jax()
    from jointplay._kernels.jax.eom import read_layout

    rpar = np.ascontiguousarray(np.atleast_2d(rpar), dtype=np.float64)
    y0 = np.ascontiguousarray(np.atleast_2d(y0), dtype=np.float64)
    t_settle = np.asarray(t_settle, dtype=np.float64).reshape(-1)
    t_end = np.asarray(t_end, dtype=np.float64).reshape(-1)
    max_step = np.asarray(max_step, dtype=np.float64).reshape(-1)
    atol = np.asarray(atol, dtype=np.float64).reshape(-1)
    chunk_size = DEFAULT_CHUNK if chunk_size is None else int(chunk_size)
    if chunk_size < 1:
        raise ConfigError(f"chunk_size must be >= 1, got {chunk_size}")
    _check(ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, method)
    layout = read_layout(ipar, rpar)
    if y0.shape[1] != layout.n_state:
        raise ConfigError(f"y0 rows must have {layout.n_state} entries, got {y0.shape[1]}")
    n = rpar.shape[0]
    _configure(jax)
    on_gpu = jax.default_backend() == "gpu"
    minimum = GPU_MIN_LANES if on_gpu and method == "explicit" else 1
    # a chunk smaller than the minimum is padded to it too (small shapes are a slow path)
    size = padded_size(n, max(chunk_size, minimum), minimum)
    compile_s = 0.0
    run_s = 0.0
    parts: list[dict[str, np.ndarray]] = []
    with _x64(jax):
        key = (layout, method, size, rpar.shape[1], y0.shape[1])
        compiled = _executables.get(key)
        for start in range(0, n, size):
            stop = min(start + size, n)
            lanes = np.arange(start, start + size)
            lanes[lanes >= stop] = start  # pad with copies of the chunk's first lane
            args = (
                rpar[lanes], y0[lanes], t_settle[lanes], t_end[lanes], max_step[lanes],
                np.float64(rtol), atol, np.int64(max_steps),
            )  # fmt: skip
            if compiled is None:
                clock = time.perf_counter()
                compiled = _compile(jax, layout, method, args)
                compile_s += time.perf_counter() - clock
                _executables[key] = compiled
            clock = time.perf_counter()
            out = jax.device_get(compiled(*args))
            run_s += time.perf_counter() - clock
            parts.append({key: np.asarray(value)[: stop - start] for key, value in out.items()})
    if timings is not None:
        timings["compile_s"] = compile_s
        timings["run_s"] = run_s
        timings["lanes"] = float(size * len(parts))  # the padded lanes that ran

    def joined(key: str, dtype: Any) -> np.ndarray:
        return np.ascontiguousarray(np.concatenate([part[key] for part in parts]), dtype=dtype)

    return BatchKernelOutput(
        peaks=joined("peaks", np.float64),
        stats=joined("stats", np.float64),
        status=joined("status", np.int64),
        t_reached=joined("t_reached", np.float64),
        n_steps=joined("n_steps", np.int64),
        n_rejected=joined("n_rejected", np.int64),
        n_rhs=joined("n_rhs", np.int64),
    )
