"""The web application of ``jointplay explore``, through Starlette's test client: every route
with good and bad input, the assets it serves (and nothing else), the download against
``jointplay simulate``, and the superseding of waiting runs."""

from __future__ import annotations

import io
import json
import threading
import time
import warnings
import zipfile

import pytest

pytest.importorskip("starlette", reason="jointplay[explore] is not installed")
pytest.importorskip("httpx", reason="Starlette's test client needs httpx")

with warnings.catch_warnings():
    # Starlette >= 1.10 asks for its httpx fork (httpx2) and warns when it finds httpx
    warnings.filterwarnings("ignore", "Using `httpx` with")
    from starlette.testclient import TestClient

from jointplay.explore.app import Runner, Superseded, create_app
from jointplay.explore.settings import load_base

QUICK = {"contact": "ifm-conventional", "settle": "1"}


@pytest.fixture(scope="module")
def client():
    app = create_app(load_base("paper-fourbar"))
    with TestClient(app, base_url="http://127.0.0.1") as test_client:
        yield test_client


def test_the_page_and_its_assets(client) -> None:
    page = client.get("/")
    assert page.status_code == 200 and "text/html" in page.headers["content-type"]
    assert "/assets/plotly.min.js" in page.text and "cdn" not in page.text.lower()
    assert page.headers["content-security-policy"].startswith("default-src 'self'")
    for name in ("explore.js", "explore.css", "plotly.min.js"):
        reply = client.get(f"/assets/{name}")
        assert reply.status_code == 200 and len(reply.content) > 100
    assert "plotly.js" in client.get("/assets/plotly.min.js").text[:400]


@pytest.mark.parametrize(
    "path",
    [
        "/assets/settings.py",
        "/assets/..%2Fsettings.py",
        "/assets/%2e%2e%2f%2e%2e%2fpyproject.toml",
        "/assets/static%2Findex.html",
        "/assets/",
        "/static/explore.js",
        "/etc/passwd",
        "/../../etc/passwd",
    ],
)
def test_no_file_outside_the_assets(client, path) -> None:
    reply = client.get(path)
    assert reply.status_code == 404
    assert "import" not in reply.text and "root:" not in reply.text


def test_only_its_own_host_names(client) -> None:
    assert client.get("/", headers={"host": "evil.example"}).status_code == 400
    assert client.get("/", headers={"host": "localhost:8765"}).status_code == 200


def test_only_get(client) -> None:
    assert client.post("/api/view", data={"rpm": "200"}).status_code == 405
    assert client.delete("/").status_code == 405


def test_spec(client) -> None:
    spec = client.get("/api/spec").json()
    assert [j["name"] for j in spec["joints"]] == ["O2", "A", "B", "O4"]
    assert spec["defaults"]["c.A"] == "21" and "ifm-conventional" in spec["contacts"]
    assert client.get("/api/spec?x=1").status_code == 400


@pytest.mark.parametrize(
    ("query", "words"),
    [
        ("c.A=abc", "must be a number"),
        ("c.A=-5", "must lie within"),
        ("evil=1", "unknown parameter"),
        ("rpm=200&rpm=300", "given twice"),
        ("contact=%3Cscript%3E", "unknown contact"),
        ("L.rocker=500", "tolerance"),
        ("settle=-1", "start-up revolutions"),
        ("mu=1e999", "finite"),
    ],
)
@pytest.mark.parametrize("route", ["/api/view", "/api/download"])
def test_bad_queries_get_one_line(client, route, query, words) -> None:
    reply = client.get(f"{route}?{query}")
    assert reply.status_code == 400
    error = reply.json()["error"]
    assert words in error and "\n" not in error and "Traceback" not in error


def test_view_changes_with_the_clearance(client) -> None:
    small = client.get("/api/view", params={**QUICK, "c.A": "5"}).json()
    large = client.get("/api/view", params={**QUICK, "c.A": "50"}).json()
    assert small["orbits"]["A"]["clearance_um"] == pytest.approx(5)
    assert large["orbits"]["A"]["clearance_um"] == pytest.approx(50)
    reach = max(map(abs, large["orbits"]["A"]["x_um"] + large["orbits"]["A"]["y_um"]))
    assert reach > 10  # the pin travels beyond where the 5 µm bearing would hold it
    assert small["peaks"]["F_A"]["value"] != large["peaks"]["F_A"]["value"]
    assert large["query"]["c.A"] == "50"
    mechanism = large["mechanism"]
    assert mechanism["frames"] == len(mechanism["crank_deg"]) and mechanism["magnification"] > 1


@pytest.mark.parametrize(
    ("contact", "integrator"), [("ifm-conventional", "dopri5"), ("ifm-ecs-spherical", "rodas4")]
)
def test_download_is_what_simulate_writes(client, contact, integrator) -> None:
    """The view and the download run the same integration (an IFM ECS method's RODAS4, the
    IFM conventional method's DOPRI5, in both), so their peaks agree to round-off."""
    query = {**QUICK, "contact": contact, "c.A": "50"}
    reply = client.get("/api/download", params=query)
    assert reply.status_code == 200
    assert reply.headers["content-type"] == "application/zip"
    archive = zipfile.ZipFile(io.BytesIO(reply.content))
    assert {"settings.toml", "summary.json", "timeseries.csv", "steps.csv"} <= set(
        archive.namelist()
    )
    summary = json.loads(archive.read("summary.json"))
    view = client.get("/api/view", params=query).json()
    assert summary["peaks"].keys() == view["peaks"].keys()
    for key, peak in view["peaks"].items():
        assert summary["peaks"][key]["value"] == pytest.approx(peak["value"], rel=1e-9)
    # the view's nominal analysis was kept from an earlier run; the command computes its own
    assert summary["nominal_peaks"] == pytest.approx(view["nominal_peaks"], rel=1e-9)
    assert summary["increase_percent"] == pytest.approx(view["increase_percent"], rel=1e-9)
    assert summary["contact"]["method"] == contact
    assert summary["solver"]["integrator"] == integrator
    assert f'method = "{contact}"' in archive.read("settings.toml").decode()


def test_joints_of_their_own_contact_cannot_be_downloaded(client) -> None:
    # jointplay simulate takes one contact for all joints: it cannot write this run
    reply = client.get("/api/download", params={**QUICK, "contact.A": "physical"})
    assert reply.status_code == 400
    assert "one contact and friction for every joint" in reply.json()["error"]
    view = client.get("/api/view", params={**QUICK, "contact.A": "physical"})
    assert view.status_code == 200 and "A: restitution law" in view.json()["contact"]


def test_a_waiting_run_is_superseded() -> None:
    runner = Runner()
    first = runner.ticket()
    release = threading.Event()
    results: list[object] = []

    def slow() -> str:
        release.wait(5)
        return "first"

    worker = threading.Thread(target=lambda: results.append(runner.run(first, slow)))
    worker.start()
    time.sleep(0.05)
    waiting = runner.ticket()
    newest = runner.ticket()
    release.set()
    worker.join()
    with pytest.raises(Superseded):
        runner.run(waiting, lambda: "stale")
    assert runner.run(newest, lambda: "newest") == "newest"
    assert results == ["first"] and runner.runs == 2


def _fake_download(release: threading.Event, counts: dict[str, int]):
    """A stand-in for :func:`engine.download` that holds its slot until ``release`` (at most
    10 s) and counts how many run at once."""
    lock = threading.Lock()

    def download(base, settings, children=None) -> bytes:
        with lock:
            counts["running"] += 1
            counts["most"] = max(counts["most"], counts["running"])
            counts["calls"] += 1
        try:
            release.wait(10)
            return b"PK\x05\x06" + bytes(18)  # an empty ZIP archive
        finally:
            with lock:
                counts["running"] -= 1

    return download


def test_downloads_run_one_at_a_time_and_the_rest_are_refused(monkeypatch) -> None:
    """Ten downloads at once (what any web page could fire at the server): one runs, nine are
    answered 429 at once, without starting anything; after it the next one runs."""
    import asyncio

    import httpx

    from jointplay.explore import engine

    release = threading.Event()
    counts = {"running": 0, "most": 0, "calls": 0}
    monkeypatch.setattr(engine, "download", _fake_download(release, counts))
    app = create_app(load_base("paper-fourbar"))

    async def main() -> tuple[httpx.Response, list[httpx.Response], httpx.Response]:
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1") as web:
            first = asyncio.create_task(web.get("/api/download", params=QUICK))
            deadline = time.monotonic() + 10
            while counts["running"] == 0 and time.monotonic() < deadline:
                await asyncio.sleep(0.01)
            asyncio.get_running_loop().call_later(2.0, release.set)  # old code: all ten wait
            others = await asyncio.gather(
                *(web.get("/api/download", params={**QUICK, "c.A": str(k + 5)}) for k in range(9))
            )
            done = await first
            after = await web.get("/api/download", params=QUICK)
            return done, others, after

    done, others, after = asyncio.run(main())
    assert counts["most"] == 1
    assert [reply.status_code for reply in others] == [429] * 9
    assert all("already running" in reply.json()["error"] for reply in others)
    assert done.status_code == 200 and after.status_code == 200
    assert counts["calls"] == 2 and app.state.runner.downloads == 2


@pytest.fixture
def stub_app(monkeypatch):
    """The app with the engine stubbed out (a view or a download costs nothing and is
    counted): what matters is whether a request reaches it."""
    from jointplay.explore import engine

    calls: list[str] = []
    monkeypatch.setattr(engine, "simulate_settings", lambda base, settings: calls.append("view"))
    monkeypatch.setattr(engine, "view", lambda run: {"peaks": {}})
    monkeypatch.setattr(
        engine,
        "download",
        lambda base, settings, children=None: calls.append("download") or b"PK\x05\x06",
    )
    app = create_app(load_base("paper-fourbar"))
    with TestClient(app, base_url="http://127.0.0.1") as test_client:
        yield test_client, calls


FOREIGN = [
    {"sec-fetch-site": "cross-site", "sec-fetch-mode": "no-cors", "sec-fetch-dest": "image"},
    {"sec-fetch-site": "same-site", "sec-fetch-mode": "cors", "sec-fetch-dest": "empty"},
    {"sec-fetch-site": "cross-site", "sec-fetch-mode": "navigate", "sec-fetch-dest": "document"},
    {"origin": "http://evil.example"},
    {"origin": "null"},
    {"origin": "http://127.0.0.1:9999"},
    {"referer": "https://evil.example/page.html"},
]


@pytest.mark.parametrize(
    "headers", FOREIGN, ids=lambda h: "+".join(f"{k}={v}" for k, v in h.items())
)
@pytest.mark.parametrize(
    "path",
    ["/api/view?settle=1", "/api/download?settle=1", "/api/spec", "/assets/explore.js"],
)
def test_another_sites_page_is_refused(stub_app, path, headers) -> None:
    """What ``<img src="http://127.0.0.1:PORT/api/download?...">`` on any site sends: refused
    with 403 and one line, before anything runs."""
    client, calls = stub_app
    reply = client.get(path, headers=headers)
    assert reply.status_code == 403
    error = reply.json()["error"]
    assert error.startswith("refused: another site's page made this request")
    assert "\n" not in error and calls == []


@pytest.mark.parametrize(
    "headers",
    [
        {},  # curl, a script
        {"sec-fetch-site": "same-origin", "sec-fetch-mode": "cors", "sec-fetch-dest": "empty"},
        {"sec-fetch-site": "same-origin", "origin": "http://127.0.0.1"},
        {"sec-fetch-site": "none", "sec-fetch-mode": "navigate"},  # typed in the address bar
        {"referer": "http://127.0.0.1/?rpm=200"},
    ],
)
@pytest.mark.parametrize("path", ["/api/view?settle=1", "/api/download?settle=1", "/api/spec"])
def test_the_pages_own_requests_are_answered(stub_app, path, headers) -> None:
    client, calls = stub_app
    assert client.get(path, headers=headers).status_code == 200
    assert len(calls) == (0 if path == "/api/spec" else 1)  # it ran


def test_a_shared_link_from_another_site_opens_the_page(stub_app) -> None:
    client, calls = stub_app
    link = {
        "sec-fetch-site": "cross-site",
        "sec-fetch-mode": "navigate",
        "sec-fetch-dest": "document",
    }
    page = client.get("/?rpm=200", headers={**link, "referer": "https://chat.example/"})
    assert page.status_code == 200 and "text/html" in page.headers["content-type"]
    # but not as an image, a script or a frame of another site's page
    for dest in ("image", "script", "iframe"):
        headers = {**link, "sec-fetch-mode": "no-cors", "sec-fetch-dest": dest}
        assert client.get("/", headers=headers).status_code == 403
    assert calls == []


@pytest.mark.parametrize("route", ["/api/view", "/api/download"])
def test_an_interference_fit_is_one_plain_line(client, route) -> None:
    """No temporary path of the server's and no class name: what is wrong and what to do."""
    reply = client.get(route, params={"c.A": "H7/s6:max"})
    assert reply.status_code == 400
    error = reply.json()["error"]
    assert "H7/s6 is an interference fit" in error and "choose a clearance fit" in error
    assert "/tmp" not in error and "jointplay-explore-" not in error
    assert "JointFit" not in error and "settings.toml" not in error


def test_errors_leave_out_internal_paths_and_class_names(stub_app, monkeypatch) -> None:
    """Whatever the readers behind the page say, the page gets no server path and no class."""
    from jointplay.errors import ConfigError
    from jointplay.explore import engine

    client, _ = stub_app

    def refuse(base, settings):
        raise ConfigError(
            "/tmp/jointplay-explore-zjwe9irt/settings.toml: JointFit: clearance must be "
            "finite and >= 0, got -4e-06"
        )

    monkeypatch.setattr(engine, "simulate_settings", refuse)
    reply = client.get("/api/view")
    assert reply.status_code == 400
    assert reply.json()["error"] == "settings.toml: clearance must be finite and >= 0, got -4e-06"

    def bug(base, settings):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(engine, "simulate_settings", bug)
    reply = client.get("/api/view")
    assert reply.status_code == 500
    error = reply.json()["error"]
    assert error.startswith("internal error (a bug): float division by zero; please report")
    assert "ZeroDivisionError" not in error


def test_a_view_past_its_step_budget_is_one_line(client, monkeypatch) -> None:
    """The budget's line, not simulate's advice about SolverOptions; the next view runs."""
    from jointplay.explore import engine

    monkeypatch.setattr(engine, "VIEW_MAX_STEPS", 2000)  # the conventional set needs ~4 000
    reply = client.get("/api/view", params={"contact": "ifm-conventional", "settle": "1"})
    assert reply.status_code == 400
    error = reply.json()["error"]
    assert error.startswith("this view needs more than 2 000 integration steps, the budget")
    assert "fewer start-up revolutions" in error and "SolverOptions" not in error
    assert client.get("/api/view", params={"settle": "0"}).status_code == 200


@pytest.mark.slow  # ~15 s of integration
def test_the_slowest_view_stops_at_its_budget(client) -> None:
    """From rest at 1 rev/min with ten start-up revolutions on the IFM ECS cylindrical set:
    93 s of the runner before the budget; now refused within it."""
    from jointplay.explore.engine import VIEW_MAX_STEPS

    query = {"rpm": "1", "start": "rest", "settle": "10", "contact": "ifm-ecs-cylindrical"}
    started = time.monotonic()
    reply = client.get("/api/view", params=query)
    seconds = time.monotonic() - started
    print(f"\nthe slowest view: refused after {seconds:.1f} s")
    assert reply.status_code == 400
    assert f"more than {VIEW_MAX_STEPS:,}".replace(",", " ") in reply.json()["error"]
    assert seconds < 60
