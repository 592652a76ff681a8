"""The web application of ``jointplay explore`` (Starlette; served by uvicorn).

Routes, and nothing else:

=====================  ===========================================================
``GET /``              the page
``GET /assets/NAME``   one of :data:`ASSETS` (the page's script and style, plotly.js)
``GET /api/spec``      the controls of the explored mechanism and their defaults
``GET /api/view?Q``    what the page draws for the settings of query ``Q`` (JSON)
``GET /api/download``  a ZIP of ``jointplay simulate``'s files for ``Q``
=====================  ===========================================================

Only the page's own requests are answered (:class:`SameOrigin`): a request that another
site's page made — ``Sec-Fetch-Site: cross-site`` or ``same-site``, an ``Origin`` or a
``Referer`` of another origin — is refused ``403``, except a link to the page ``/`` itself
followed from elsewhere (a shared link); a request without those headers (curl, a script)
is answered.

A query is read by :func:`jointplay.explore.settings.parse_query`: an unknown, repeated or bad
parameter is answered ``400`` with ``{"error": ...}`` in one line. Views run one at a time in a
worker thread; a request that is still waiting when a newer one arrives is not run (``409``,
superseded) — the page has moved on and discards it too. Downloads run beside them, at most
:data:`MAX_DOWNLOADS` at a time; one more is answered ``429`` at once (nothing queues, so no
page can pile up work on the server).
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import re
import threading
import time
from collections.abc import AsyncIterator, Callable
from importlib import resources
from typing import Any, TypeVar

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route
from starlette.types import ASGIApp, Receive, Scope, Send

from jointplay.errors import JointplayError
from jointplay.explore.settings import Base, Settings, parse_query

T = TypeVar("T")

#: The files the page loads, by name: (package, resource path, media type).
ASSETS: dict[str, tuple[str, str, str]] = {
    "explore.js": ("jointplay.explore", "static/explore.js", "text/javascript; charset=utf-8"),
    "explore.css": ("jointplay.explore", "static/explore.css", "text/css; charset=utf-8"),
    "plotly.min.js": ("plotly", "package_data/plotly.min.js", "text/javascript; charset=utf-8"),
}
#: Host names the server answers to (a guard against DNS rebinding: another site's page
#: cannot reach it under its own name).
HOSTS = ("127.0.0.1", "localhost", "[::1]", "::1")
#: Security headers of every page and asset: no framing, no foreign scripts.
HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' data:; style-src 'self' 'unsafe-inline'; script-src 'self'",
    "X-Content-Type-Options": "nosniff",
    "X-Frame-Options": "DENY",
}


#: Downloads (each a ``jointplay simulate`` process) that may run at once, beside the one view.
MAX_DOWNLOADS = 1


#: The answer to a download beyond :data:`MAX_DOWNLOADS`.
BUSY = (
    "a download is already running (jointplay simulate, one at a time): wait for it to "
    "finish, then download again"
)


#: The answer to a request still running when the server stops (Ctrl-C, SIGTERM) and its
#: grace (``timeout_graceful_shutdown``) has run out.
STOPPING = "the server is stopping: start jointplay explore again"


class Superseded(Exception):
    """A newer request arrived before this one ran."""


class Busy(Exception):
    """Every download slot is taken."""


class Runner:
    """Runs one view at a time (a waiting run that a newer one supersedes is skipped) and at
    most ``downloads`` downloads beside it (one more is refused at once, :class:`Busy`)."""

    def __init__(self, downloads: int = MAX_DOWNLOADS) -> None:
        self._lock = threading.Lock()
        self._tickets = itertools.count(1)
        self._latest = 0
        self._slots = threading.BoundedSemaphore(downloads)
        self.runs = 0  # simulations run (for tests and the log)
        self.downloads = 0  # downloads run

    def slot(self) -> None:
        """Take a download slot, or raise :class:`Busy` when none is free (never waits: a
        refused download costs nothing). Give it back with :meth:`release`."""
        if not self._slots.acquire(blocking=False):
            raise Busy
        self.downloads += 1

    def release(self) -> None:
        """Give back the download slot that :meth:`slot` took."""
        self._slots.release()

    def ticket(self) -> int:
        """A number for a new request; it supersedes every earlier one still waiting."""
        number = next(self._tickets)
        self._latest = number
        return number

    def run(self, ticket: int, work: Callable[[], T]) -> T:
        with self._lock:
            if ticket != self._latest:
                raise Superseded
            self.runs += 1
            return work()


#: ``Sec-Fetch-Site`` values of a request that another site's page made.
FOREIGN_SITES = ("cross-site", "same-site")


def foreign(scope: Scope) -> str | None:
    """Why an HTTP request comes from another site's page (in words), or ``None`` when it
    may be answered: from the page itself, typed into the address bar, or without the
    browser's headers (curl, a script).

    A top-level navigation to the page ``/`` from another site (a shared link clicked in a
    chat or mail) is answered: the page starts nothing, and its own requests are checked.
    """
    headers = {
        key.decode("latin-1").lower(): value.decode("latin-1") for key, value in scope["headers"]
    }
    own = f"{scope.get('scheme', 'http')}://{headers.get('host', '')}".lower()
    page = scope.get("path") == "/"
    site = headers.get("sec-fetch-site", "").strip().lower()
    if site in FOREIGN_SITES:
        navigation = (
            headers.get("sec-fetch-mode", "").lower() == "navigate"
            and headers.get("sec-fetch-dest", "document").lower() == "document"
        )
        if not (page and navigation):
            return f"Sec-Fetch-Site: {site}"
    origin = headers.get("origin")
    if origin is not None and origin.strip().lower() != own:
        return f"Origin: {origin.strip()[:80]}"
    referer = headers.get("referer")
    if referer and not page and _origin_of(referer) != own:
        return f"Referer from {_origin_of(referer)[:80]}"
    return None


def _origin_of(url: str) -> str:
    """``scheme://host[:port]`` of ``url``, lower case."""
    from urllib.parse import urlsplit

    try:
        parts = urlsplit(url.strip())
    except ValueError:
        return "?"
    return f"{parts.scheme}://{parts.netloc}".lower()


class SameOrigin:
    """ASGI middleware: refuses (``403``, one line) a request that another site's page made
    (:func:`foreign`), before any route runs."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            why = foreign(scope)
            if why is not None:
                reply = _error(
                    f"refused: another site's page made this request ({why}); jointplay "
                    "explore answers only its own page: open its address in the browser",
                    403,
                )
                await reply(scope, receive, send)
                return
        await self.app(scope, receive, send)


def _read(package: str, path: str) -> bytes:
    return (resources.files(package) / path).read_bytes()


def _error(message: str, status: int = 400) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status, headers=HEADERS)


def create_app(base: Base, *, hosts: tuple[str, ...] = HOSTS) -> Starlette:
    """The application exploring ``base``; it answers requests addressed to ``hosts``."""
    from jointplay.explore import engine

    runner = Runner()
    children = engine.Children()  # the downloads' processes, ended with the server
    files = {name: _read(package, path) for name, (package, path, _) in ASSETS.items()}
    index = _read("jointplay.explore", "static/index.html")

    async def page(request: Request) -> Response:
        # The page reads its own query and reports a bad one beside the controls.
        return Response(index, media_type="text/html; charset=utf-8", headers=HEADERS)

    async def asset(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in files:  # only the named files, never a path
            return _error(f"no asset {name[:60]!r}", 404)
        return Response(files[name], media_type=ASSETS[name][2], headers=HEADERS)

    async def spec(request: Request) -> Response:
        if request.query_params:
            return _error("/api/spec takes no parameters")
        return JSONResponse(base.spec(), headers=HEADERS)

    def simulated(settings: Settings) -> dict[str, Any]:
        """The view of ``settings``, with the server's time and the canonical query."""
        started = time.perf_counter()
        out = engine.view(engine.simulate_settings(base, settings))
        out["server_s"] = time.perf_counter() - started
        out["query"] = settings.query()
        return out

    async def view(request: Request) -> Response:
        try:
            settings = parse_query(base, request.query_params)
            ticket = runner.ticket()  # supersedes every request still waiting
            data = await run_in_threadpool(runner.run, ticket, lambda: simulated(settings))
        except Superseded:
            return _error("superseded by a newer request", 409)
        except JointplayError as exc:
            return _error(_line(exc))
        except Exception as exc:  # a bug: one line to the page and the console
            return _bug(exc)
        except asyncio.CancelledError:  # stopping, past the grace: no traceback on the console
            return _error(STOPPING, 503)
        return JSONResponse(data, headers=HEADERS)

    async def download(request: Request) -> Response:
        try:
            settings = parse_query(base, request.query_params)
            runner.slot()
        except Busy:
            return _error(BUSY, 429)
        except JointplayError as exc:
            return _error(_line(exc))
        try:
            archive = await run_in_threadpool(engine.download, base, settings, children)
        except JointplayError as exc:
            return _error(_line(exc))
        except Exception as exc:
            return _bug(exc)
        except asyncio.CancelledError:
            return _error(STOPPING, 503)
        finally:
            runner.release()
        name = f"jointplay-{base.name}.zip"
        return Response(
            archive,
            media_type="application/zip",
            headers={**HEADERS, "Content-Disposition": f'attachment; filename="{name}"'},
        )

    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        try:
            yield
        finally:  # the server stops: no download's simulate outlives it
            await run_in_threadpool(children.end)

    app = Starlette(
        lifespan=lifespan,
        routes=[
            Route("/", page, methods=["GET"]),
            Route("/assets/{name}", asset, methods=["GET"]),
            Route("/api/spec", spec, methods=["GET"]),
            Route("/api/view", view, methods=["GET"]),
            Route("/api/download", download, methods=["GET"]),
        ],
        middleware=[
            Middleware(TrustedHostMiddleware, allowed_hosts=list(hosts)),
            Middleware(SameOrigin),
        ],
    )
    app.state.runner = runner
    app.state.children = children
    return app


def _bug(exc: Exception) -> JSONResponse:
    """A ``500`` for an unexpected error, said in one line on the page and on the server's
    console (with the traceback when ``JOINTPLAY_DEBUG=1``, as the command line does)."""
    import os
    import sys
    import traceback

    line = (
        f"internal error (a bug): {_line(exc)}; please report it to the jointplay maintainers "
        "with the page's address"
    )
    # the console, the user's own, also gets the exception's class
    print(f"jointplay explore: {line} ({type(exc).__name__})", file=sys.stderr)
    if os.environ.get("JOINTPLAY_DEBUG"):
        traceback.print_exception(exc)
    return _error(line, 500)


#: A path into a folder of the server's own (the configuration file it writes for a run).
_INTERNAL_PATH = re.compile(r"""(?:[A-Za-z]:)?[^\s'"]*jointplay-explore-[^\s'"/\\]*[/\\]""")
#: A class name that starts an error message (``JointFit: ...``), Python's own or ours.
_CLASS_NAME = re.compile(r"\b(?:[A-Z][a-z0-9]+){2,}: ")


def _line(exc: BaseException) -> str:
    """An error in one line (at most 600 characters), without the server's internal paths
    (its temporary folders) or the class names of the code that raised it."""
    text = " ".join(str(exc).split())
    text = _CLASS_NAME.sub("", _INTERNAL_PATH.sub("", text))
    return text if len(text) <= 600 else text[:597] + "..."
