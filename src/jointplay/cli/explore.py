"""``jointplay explore``: the mechanism live in the browser (a local web app)."""

from __future__ import annotations

import socket
import sys
import threading
from types import FrameType
from typing import Annotated

import typer

from jointplay.cli._app import app
from jointplay.cli._common import ConfigOption, PresetOption, compiling_kernels
from jointplay.errors import ConfigError, Interrupted

#: The packages of the web app and where they come from.
INSTALL_HINT = "pip install 'jointplay[explore]' (Starlette, uvicorn and plotly)"


def _check_installed() -> None:
    """A clear line when the web app's packages are missing."""
    import importlib.util

    missing = [
        name
        for name in ("starlette", "uvicorn", "plotly")
        if importlib.util.find_spec(name) is None
    ]
    if missing:
        raise ConfigError(
            f"jointplay explore needs {', '.join(missing)}, which are not installed: {INSTALL_HINT}"
        )


@app.command("explore")
def explore_command(
    preset: PresetOption = None,
    config: ConfigOption = None,
    port: Annotated[
        int,
        typer.Option("--port", help="Port to serve on (0: any free port).", min=0, max=65535),
    ] = 8765,
    host: Annotated[
        str,
        typer.Option(
            "--host",
            help="Address to serve on: 127.0.0.1 (default) keeps the app on this machine; "
            "0.0.0.0 serves every network interface.",
        ),
    ] = "127.0.0.1",
    browser: Annotated[
        bool,
        typer.Option("--browser/--no-browser", help="Open the page in the web browser."),
    ] = True,
) -> None:
    """Explore the mechanism live in the browser: move a slider, see the pins rattle.

    Serves a local page (http://127.0.0.1:8765/ by default) with the crank speed, each joint's
    clearance or ISO 286 fit, the contact law, friction, the link lengths within their
    tolerance and the start; every change re-simulates one revolution and redraws the
    mechanism, the journal orbits, the joint forces, the output speed, the torque, the peaks
    and the diagnostics. The page's URL holds its settings. Ctrl-C stops the server.
    """
    _check_installed()
    import uvicorn

    from jointplay.explore.app import HOSTS, create_app
    from jointplay.explore.engine import simulate_settings
    from jointplay.explore.settings import load_base, parse_query

    base = load_base(preset, None if config is None else str(config))
    children = None
    sock = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        raise ConfigError(
            f"cannot serve on {host}:{port}: {exc.strerror or exc}; give another --port (0: any free one)"
        ) from None
    try:
        with compiling_kernels():  # the first view is then as quick as the next
            simulate_settings(base, parse_query(base, {}))
        bound = sock.getsockname()[1]
        shown = f"[{host}]" if ":" in host else host
        url = f"http://{shown}:{bound}/"
        if host in ("0.0.0.0", "::"):  # every interface: any name that reaches it
            hosts: tuple[str, ...] = ("*",)
            print(
                "jointplay explore: warning: serving on every network interface; anyone who "
                "can reach this machine can use the page",
                file=sys.stderr,
            )
        elif host in ("127.0.0.1", "localhost", "::1"):
            hosts = HOSTS
        else:
            hosts = (*HOSTS, host, shown)
        application = create_app(base, hosts=tuple(hosts))
        children = application.state.children

        class Server(uvicorn.Server):
            """uvicorn's server that, the moment SIGTERM or SIGINT arrives, also stops the
            downloads' ``jointplay simulate`` processes (else they would run on, orphaned)."""

            def handle_exit(self, sig: int, frame: FrameType | None) -> None:
                application.state.children.end(wait=0)
                super().handle_exit(sig, frame)

        server = Server(
            uvicorn.Config(application, log_level="warning", timeout_graceful_shutdown=5)
        )
        where = f"{base.name} at {url}"
        announce = (server, where, url if browser else None)
        threading.Thread(target=_announce, args=announce, daemon=True).start()
        server.run(sockets=[sock])
    except (KeyboardInterrupt, Interrupted):
        pass  # uvicorn has shut down; it raises the signal it caught again
    finally:
        sock.close()
        if children is not None:
            children.end()  # those that SIGTERM did not end within the wait: killed
    print("jointplay explore: stopped", file=sys.stderr)


def _announce(server: object, where: str, url: str | None) -> None:
    """Once the server answers: say where (one line on stdout), and open ``url`` in the
    browser unless ``None``."""
    import time
    import webbrowser

    while not getattr(server, "started", False):
        if getattr(server, "should_exit", False):
            return
        time.sleep(0.02)
    print(f"jointplay explore: {where} (Ctrl-C stops)", flush=True)
    if url is not None:
        webbrowser.open(url)
