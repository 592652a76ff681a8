"""Bad input, command by command: exit status 2, one line naming the culprit, --out untouched.

Each case is what a user could type. The contract (README, "Exit codes"): bad input or an
unusable environment gives exit status 2 and one line on stderr that names the option, field
or file at fault; no traceback, no exit 3; the output folder is left exactly as it was and no
temporary folder is left beside it.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from _errors import assert_one_line_error
from jointplay.cli import run
from jointplay.io.output import MARKER

PAPER = """
[mechanism]
name = "bad"
branch = {branch}
[geometry]
crank = "{crank}"
coupler = "270.5 mm"
rocker = "270.5 mm"
ground = "279.4 mm"
[driver]
speed = "{speed}"
[joints.A]
diameter = "10 mm"
fit = "H8/g7"
clearance = "0.021 mm"
[tolerances]
general = "c"
"""


def _config(
    folder: Path,
    name: str,
    *,
    branch: str = "1",
    crank: str = "108 mm",
    speed: str = "200 rpm",
    extra: str = "",
) -> str:
    path = folder / name
    text = PAPER.format(branch=branch, crank=crank, speed=speed)
    path.write_text(text + extra, encoding="utf-8")
    return str(path)


@pytest.fixture
def files(tmp_path: Path) -> dict[str, str]:
    """Input files for the cases, by name."""
    made = {
        "branch_nan": _config(tmp_path, "branch_nan.toml", branch="nan"),
        "branch_inf": _config(tmp_path, "branch_inf.toml", branch="inf"),
        "branch_half": _config(tmp_path, "branch_half.toml", branch="1.5"),
        "huge_crank": _config(tmp_path, "huge.toml", crank="1e30 mm"),
        "rtol_abc": _config(tmp_path, "rtol.toml", extra='[simulation]\nrtol = "abc"\n'),
        "integrator_euler": _config(
            tmp_path, "integrator.toml", extra='[simulation]\nintegrator = "euler"\n'
        ),
        "revolutions_abc": _config(
            tmp_path, "revs.toml", extra='[simulation]\nrevolutions = "abc"\n'
        ),
        "friction_abc": _config(tmp_path, "fric.toml", extra='[simulation]\nfriction = "abc"\n'),
        "simulation_list": _config(tmp_path, "list.toml", extra="[simulation]\nk = [1, 2]\n"),
        "huge_speed_config": _config(tmp_path, "fast.toml", speed="1e300 rpm"),
        "huge_deviation": _config(
            tmp_path,
            "deviation.toml",
            extra='[tolerances.lengths.crank]\nlower = "-1e30 mm"\nupper = "1e30 mm"\n',
        ),
    }
    latin1 = tmp_path / "latin1.toml"
    latin1.write_bytes(
        PAPER.format(branch="1", crank="108 mm", speed="200 rpm")
        .replace("bad", "b\xe9")
        .encode("latin-1")
    )
    made["latin1"] = str(latin1)
    malformed = tmp_path / "malformed.toml"
    malformed.write_text("[mechanism\nname = ", encoding="utf-8")
    made["malformed"] = str(malformed)
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    made["fifo"] = str(fifo)
    made["clearance_zero"] = _config(
        tmp_path,
        "zero.toml",
        extra='[tolerances.joints.A]\nclearance_min = "0 um"\nclearance_max = "20 um"\n',
    )
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "[" * 2000 + "]" * 2000 + "\n", encoding="utf-8")
    made["deep"] = str(deep)
    dotted = tmp_path / "dotted.toml"
    dotted.write_text(".".join(["k"] * 40) + " = 1\n", encoding="utf-8")
    made["dotted"] = str(dotted)
    made["folder"] = str(tmp_path)
    for name, rows in {
        "huge_speed": "0,1e308\n90,-1e308\n",
        "huge_angle": "1e300,10\n90,12\n",
        "duplicate_angle": "90,10\n90,12\n180,11\n",
        "text_speed": "0,fast\n90,12\n",
    }.items():
        path = tmp_path / f"{name}.csv"
        path.write_text("crank_deg,speed\n" + rows, encoding="utf-8")
        made[name] = str(path)
    return made


# (command line, culprit in the message); "{name}" is replaced by files[name].
CASES: dict[str, tuple[list[str], str]] = {
    # simulate: numbers
    "simulate friction nan": (["simulate", "--friction", "nan"], "--friction"),
    "simulate friction negative": (["simulate", "--friction", "-0.1"], "--friction"),
    "simulate restitution with impact": (["simulate", "--restitution", "1.5"], "impact"),
    "simulate restitution nan": (["simulate", "--restitution", "nan"], "--restitution"),
    "simulate restitution out of range": (
        ["simulate", "--contact", "hunt-crossley", "--k", "1e4 N/mm^1.5", "--restitution", "1.5"],
        "restitution",
    ),
    "simulate cmax with hertz": (
        ["simulate", "--contact", "hertz", "--k", "1e4 N/mm^1.5", "--cmax", "10 N*s/mm"],
        "--cmax",
    ),
    "simulate damping with hertz": (
        ["simulate", "--contact", "hertz", "--k", "1e4 N/mm^1.5", "--damping", "100 N*s/m"],
        "--damping",
    ),
    "simulate kelvin-voigt stiffness N/mm^1.5": (
        ["simulate", "--contact", "kelvin-voigt", "--k", "1e4 N/mm^1.5", "--damping", "1 N*s/m"],
        "--k",
    ),
    "simulate kelvin-voigt exponent": (
        [
            "simulate",
            "--contact",
            "kelvin-voigt",
            "--k",
            "1e7 N/m",
            "--exponent",
            "1.5",
            "--damping",
            "1 N*s/m",
        ],
        "--exponent",
    ),
    "simulate kelvin-voigt without damping": (
        ["simulate", "--contact", "kelvin-voigt", "--k", "1e7 N/m"],
        "damping",
    ),
    "simulate stiffness without unit": (["simulate", "--k", "1e4"], "--k"),
    "simulate stiffness wrong unit": (["simulate", "--k", "1e4 N"], "--k"),
    "simulate exponent zero": (["simulate", "--exponent", "0"], "--exponent"),
    "simulate unknown law": (["simulate", "--contact", "glue"], "glue"),
    "simulate law needs stiffness": (
        ["simulate", "--contact", "kelvin-voigt", "--damping", "100 N*s/m"],
        "stiffness",
    ),
    "simulate clearance 1 m": (["simulate", "--clearance", "1 m"], "clearance"),
    "simulate clearance negative": (["simulate", "--clearance", "-1 um"], "clearance"),
    "simulate clearance text": (["simulate", "--clearance", "wide"], "--clearance"),
    "simulate clearance power": (["simulate", "--clearance", "10**10**10 mm"], "--clearance"),
    "kinematics gravity 1e300": (
        ["kinematics", "--no-plots", "--gravity", "1e300 m/s^2"],
        "--gravity must be at most 1000 m/s²",
    ),
    "kinematics start angle 1e300": (
        ["kinematics", "--no-plots", "--start-angle", "1e300 deg"],
        "--start-angle must lie within ±720°",
    ),
    "simulate start angle 721 deg": (
        ["simulate", "--start-angle", "721 deg"],
        "--start-angle must lie within ±720°",
    ),
    "tolerance gravity 1e300": (
        ["tolerance", "--samples", "10", "--gravity", "1e300 m/s^2"],
        "--gravity must be at most 1000 m/s²",
    ),
    "kinematics rpm decimal comma": (
        ["kinematics", "--no-plots", "--rpm", "200,5 rpm"],
        "--rpm: cannot read '200,5 rpm' as a quantity: ',' at character 4: decimal comma? "
        "write '200.5 rpm'",
    ),
    "kinematics gravity decimal comma": (
        ["kinematics", "--no-plots", "--gravity", "9,81 m/s^2"],
        "decimal comma? write '9.81 m/s^2'",
    ),
    "kinematics rpm comparison": (
        ["kinematics", "--no-plots", "--rpm", "200 rpm > 5"],
        "--rpm: cannot read '200 rpm > 5' as a quantity: '>' (character 9)",
    ),
    "kinematics rpm two numbers": (
        ["kinematics", "--no-plots", "--rpm", "2 00 rpm"],
        "a second number '00' (character 3)",
    ),
    "simulate output step 1 ns": (["simulate", "--output-step", "1 ns"], "--output-step"),
    "simulate output step zero": (["simulate", "--output-step", "0 s"], "output step"),
    "simulate sample-deg tiny": (["simulate", "--sample-deg", "1e-9 deg"], "--sample-deg"),
    "simulate sample-deg bare": (
        ["simulate", "--sample-deg", "5"],
        "--sample-deg: '5' has no unit",
    ),
    "simulate sample-deg zero": (["simulate", "--sample-deg", "0 deg"], "--sample-deg"),
    "simulate rtol nan": (["simulate", "--rtol", "nan"], "rtol"),
    "simulate rtol large": (["simulate", "--rtol", "0.5"], "rtol"),
    "simulate integrator unknown": (
        ["simulate", "--integrator", "euler"],
        "--integrator must be radau, rodas4 or dopri5, got 'euler'",
    ),
    "simulate revolutions zero": (["simulate", "--revolutions", "0"], "--revolutions"),
    "simulate revolutions inf": (["simulate", "--revolutions", "inf"], "--revolutions"),
    "simulate revolutions text": (["simulate", "--revolutions", "abc"], "--revolutions"),
    "simulate settle negative": (["simulate", "--settle", "-1"], "--settle"),
    "simulate max step zero": (["simulate", "--max-step", "0 s"], "max_step"),
    "simulate atol bare": (["simulate", "--atol", "1e-12"], "--atol: '1e-12' has no unit"),
    "simulate atol large": (["simulate", "--atol", "1 mm"], "--atol must be a length > 0"),
    "simulate onset zero": (["simulate", "--onset-tolerance", "0 m"], "--onset-tolerance"),
    "simulate onset beyond the clearance": (
        ["simulate", "--onset-tolerance", "30 um"],
        "--onset-tolerance 3e-05 m is not below the smallest clearance 2.1e-05 m",
    ),
    "simulate joints empty": (["simulate", "--joints", " , "], "--joints"),
    "simulate joints unknown": (["simulate", "--joints", "Q7"], "Q7"),
    "simulate start unknown": (["simulate", "--start", "sideways"], "sideways"),
    "simulate ramp time without ramp": (["simulate", "--ramp-time", "10 ms"], "ramp"),
    "simulate method unknown": (["simulate", "--method", "magic"], "magic"),
    "simulate method with k": (
        ["simulate", "--method", "ifm-conventional", "--k", "1e4 N/mm^1.5"],
        "--method",
    ),
    "simulate ecs-source without method": (["simulate", "--ecs-source", "paper"], "--ecs-source"),
    "simulate friction law unknown": (
        ["simulate", "--friction", "0.1", "--friction-law", "sticky"],
        "--friction-law",
    ),
    "simulate format unknown": (["simulate", "--format", "xls"], "--format"),
    "simulate rpm nan": (["simulate", "--rpm", "nan rpm"], "--rpm"),
    "simulate rpm bare": (
        ["simulate", "--rpm", "200"],
        "--rpm: '200' has no unit; write it with one, e.g. \"200 rpm\"",
    ),
    "simulate rpm length": (["simulate", "--rpm", "200 mm"], "--rpm"),
    "simulate rpm negative": (["simulate", "--rpm", "-5 rpm"], "--rpm must be a positive"),
    "simulate direction": (["simulate", "--direction", "up"], "--direction"),
    "simulate start angle length": (["simulate", "--start-angle", "1 m"], "--start-angle"),
    "simulate gravity length": (["simulate", "--gravity", "9.81 m"], "--gravity"),
    "simulate unknown option": (["simulate", "--bogus", "1"], "--bogus"),
    "simulate unknown preset": (["simulate", "--preset", "tribar"], "tribar"),
    "simulate preset and config": (
        ["simulate", "-p", "paper-fourbar", "-c", "{branch_nan}"],
        "either",
    ),
    # configuration files
    "config missing": (["simulate", "--config", "/nonexistent/x.toml"], "not found"),
    "config fifo": (["simulate", "--config", "{fifo}"], "regular file"),
    "config folder": (["simulate", "--config", "{folder}"], "folder"),
    "config not utf-8": (["simulate", "--config", "{latin1}"], "UTF-8"),
    "config malformed": (["simulate", "--config", "{malformed}"], "malformed TOML"),
    "config branch nan": (["kinematics", "--config", "{branch_nan}"], "branch"),
    "config branch inf": (["kinematics", "--config", "{branch_inf}"], "branch"),
    "config branch 1.5": (["kinematics", "--config", "{branch_half}"], "branch"),
    "config absurd length": (["kinematics", "--config", "{huge_crank}"], "geometry.crank"),
    "config absurd length tolerance": (["tolerance", "--config", "{huge_crank}"], "geometry"),
    "config rtol text": (["simulate", "--config", "{rtol_abc}"], "simulation.rtol"),
    "config integrator unknown": (
        ["simulate", "--config", "{integrator_euler}"],
        "--integrator must be radau, rodas4 or dopri5, got 'euler'",
    ),
    "config revolutions text": (["simulate", "--config", "{revolutions_abc}"], "revolutions"),
    "config friction text": (["simulate", "--config", "{friction_abc}"], "friction"),
    "config stiffness list": (["simulate", "--config", "{simulation_list}"], "simulation.k"),
    # kinematics
    "kinematics step nan": (["kinematics", "--step", "nan deg"], "step"),
    "kinematics step bare": (["kinematics", "--step", "1"], "--step: '1' has no unit"),
    "kinematics step not dividing 360": (["kinematics", "--step", "0.7 deg"], "divide"),
    "kinematics method": (["kinematics", "--method", "guess"], "guess"),
    "kinematics step tiny": (["kinematics", "--step", "1e-9 deg"], "--step"),
    "kinematics rpm 1e300": (["kinematics", "--rpm", "1e300 rpm"], "--rpm"),
    "simulate rpm 1e300": (["simulate", "--rpm", "1e300 rad/s"], "--rpm"),
    "tolerance rpm inf": (["tolerance", "--rpm", "inf rpm"], "--rpm"),
    "tolerance rpm bare": (["tolerance", "--rpm", "200"], "--rpm: '200' has no unit"),
    "config absurd deviation": (["tolerance", "--config", "{huge_deviation}"], "crank"),
    "config absurd speed": (["kinematics", "--config", "{huge_speed_config}"], "driver.speed"),
    # tolerance
    "tolerance samples zero": (["tolerance", "--samples", "0"], "--samples"),
    "tolerance revolutions zero": (
        ["tolerance", "--responses", "dynamic", "--revolutions", "0"],
        "--revolutions",
    ),
    "tolerance contact for kinematic": (["tolerance", "--contact", "hertz"], "dynamic"),
    "tolerance restitution with impact": (
        ["tolerance", "--responses", "dynamic", "--restitution", "1.5"],
        "impact",
    ),
    "tolerance malformed dask address": (
        ["tolerance", "--dask-scheduler", "not a url::"],
        "--dask-scheduler",
    ),
    "tolerance workers and dask": (
        ["tolerance", "--workers", "2", "--dask-scheduler", "tcp://127.0.0.1:8786"],
        "--workers",
    ),
    "tolerance spec limit": (["tolerance", "--spec-limit", "omega4_peak"], "omega4_peak"),
    "tolerance method": (["tolerance", "--method", "guess"], "--method"),
    # compare
    "compare speeds 1e308": (["compare", "-m", "{huge_speed}", "--method", "nominal"], "speed"),
    "compare angle 1e300": (["compare", "-m", "{huge_angle}", "--method", "nominal"], "crank_deg"),
    "compare duplicate angles": (
        ["compare", "-m", "{duplicate_angle}", "--method", "nominal"],
        "90",
    ),
    "compare text speed": (["compare", "-m", "{text_speed}", "--method", "nominal"], "fast"),
    "compare measurements fifo": (["compare", "-m", "{fifo}"], "regular file"),
    "compare low speed": (["compare", "--low-speed", "2"], "--low-speed"),
    "compare revolutions": (["compare", "--revolutions", "0.5"], "--revolutions"),
    "compare unit": (["compare", "--unit", "furlongs"], "--unit"),
    "compare angle origin": (["compare", "--angle-origin", "1e308 deg"], "--angle-origin"),
    "compare method": (["compare", "--method", "magic"], "magic"),
    # ecs
    "ecs restitution": (["ecs", "--restitution", "1.5"], "--restitution"),
    "ecs rpm text": (["ecs", "--rpm", "fast"], "--rpm"),
    "ecs sweep": (["ecs", "--sweep", "1:0:5 rpm"], "--sweep"),
    "ecs sweep bare": (["ecs", "--sweep", "100,200"], "--sweep: '100,200' has no unit"),
    "ecs rpm bare": (["ecs", "--rpm", "200"], "--rpm: '200' has no unit"),
    "ecs damping ratio": (["ecs", "--damping-ratio", "nan s"], "--damping-ratio"),
    "ecs damping ratio bare": (
        ["ecs", "--damping-ratio", "0.01"],
        "--damping-ratio: '0.01' has no unit",
    ),
    "wear hours bare": (
        ["wear", "--hours", "600", "--clearance-limit", "+20 um"],
        "--hours: '600' has no unit; write it with one, e.g. \"600 h\"",
    ),
    # paper
    "paper rpm zero": (["paper", "--rpm", "0"], "--rpm"),
    "paper revolutions nan": (["paper", "--revolutions", "nan"], "--revolutions"),
    "paper ecs source": (["paper", "--ecs-source", "guess"], "--ecs-source"),
    "paper revolutions 1e9": (["paper", "--revolutions", "1e9"], "more than 10000 revolutions"),
    "design require two comparisons": (
        ["design", "--fits", "H8/g7", "--classes", "c", "-r", "joint_force <= <= 150 N"],
        "requirement 'joint_force <= <= 150 N': one comparison only, found '<=' and then '<='",
    ),
    "tolerance require flipped": (
        ["tolerance", "--samples", "10", "--require", "joint_force >= <= 150 N"],
        "one comparison only, found '>=' and then '<='",
    ),
    "design clearance limit negative": (
        ["design", "-r", "life >= 200 h", "--clearance-limit", "-20 um"],
        "a radial clearance is > 0",
    ),
    "wear clearance allowance negative": (
        ["wear", "--hours", "600 h", "--clearance-limit", "+-5 um"],
        "an allowance >= 0",
    ),
    "tolerance clearance_min zero": (
        ["tolerance", "--config", "{clearance_zero}", "--responses", "dynamic"],
        "needs a radial clearance > 0",
    ),
    # every number bounded before use
    "tolerance samples 1e23": (
        ["tolerance", "--samples", "99999999999999999999999"],
        "less than or equal to 10000000",
    ),
    "design samples 1e23": (
        ["design", "-r", "rocker_swing >= 50 deg", "--samples", "99999999999999999999999"],
        "--samples",
    ),
    "tolerance workers 1e23": (["tolerance", "--workers", "99999999999999999999999"], "--workers"),
    "tolerance revolutions 1e9": (
        ["tolerance", "--responses", "dynamic", "--revolutions", "1e9"],
        "more than 10000 revolutions",
    ),
    "simulate revolutions 1e6": (["simulate", "--revolutions", "1e6"], "--revolutions 1e+06"),
    # every file read through the one bounded reader
    "design table fifo": (
        ["design", "-r", "rocker_swing >= 50 deg", "--table", "{fifo}"],
        "is not a regular file",
    ),
    "wear table /dev/zero": (
        ["wear", "--hours", "600 h", "--clearance-limit", "+20 um", "--table", "/dev/zero"],
        "'/dev/zero' is not a regular file",
    ),
    "wear table latin-1": (
        ["wear", "--hours", "600 h", "--clearance-limit", "+20 um", "--table", "{latin1}"],
        "is not UTF-8 text",
    ),
    "design table nested": (
        ["design", "-r", "rocker_swing >= 50 deg", "--table", "{deep}"],
        "nested deeper than 16 levels",
    ),
    "simulate config nested": (["simulate", "--config", "{deep}"], "nested deeper"),
    "simulate config dotted keys": (["simulate", "--config", "{dotted}"], "nested deeper"),
    # fit and general-tolerance (no --out)
    "fit size 1e-300 mm": (["fit", "H8/g7", "--size", "1e-300 mm"], "1e-300"),
    "fit size negative": (["fit", "H8/g7", "--size", "-5 mm"], "--size"),
    "fit size bare": (["fit", "H8/g7", "--size", "10"], "--size"),
    "fit designation": (["fit", "Q8/z0", "--size", "10 mm"], "Q8"),
    "general-tolerance class": (["general-tolerance", "x", "--size", "10 mm"], "x"),
    "general-tolerance size huge": (["general-tolerance", "c", "--size", "1e30 mm"], "1e+30"),
    "show unknown preset": (["show", "tribar"], "tribar"),
}

NO_OUT = ("fit", "general-tolerance", "show", "presets")


@pytest.fixture
def previous(tmp_path: Path) -> Path:
    """An earlier complete result in --out, which a failed run must leave as it was."""
    out = tmp_path / "results" / "run"
    out.mkdir(parents=True)
    (out / MARKER).write_text("{}\n", encoding="utf-8")
    (out / "summary.json").write_text('{"earlier": true}\n', encoding="utf-8")
    return out


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_the_suite_is_large_enough() -> None:
    assert len(CASES) >= 60


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_bad_input_is_one_line_exit_2_and_leaves_out_alone(
    case: str, files: dict[str, str], previous: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    arguments, culprit = CASES[case]
    argv = [a.format(**files) if "{" in a else a for a in arguments]
    if argv[0] not in NO_OUT:
        argv += ["--out", str(previous)]
    before = _snapshot(previous)
    status = run(argv)
    assert_one_line_error(status, capsys.readouterr().err, culprit)
    assert _snapshot(previous) == before
    leftovers = [p.name for p in previous.parent.iterdir() if p.name != previous.name]
    assert leftovers == []


# --- the output folder itself --------------------------------------------------------------------


@pytest.mark.parametrize(
    ("out", "culprit"),
    [("", "--out"), (".", "--out"), ("/proc/jointplay-x", "is a system folder")],
    ids=["empty", "dot", "proc"],
)
def test_unusable_out_is_refused_before_computing(
    out: str, culprit: str, capsys: pytest.CaptureFixture[str]
) -> None:
    status = run(["kinematics", "--no-plots", "--out", out])
    err = capsys.readouterr().err
    assert status == 2, err
    assert len(err.strip().splitlines()) == 1 and culprit in err


@pytest.mark.parametrize(
    "command",
    [
        ["simulate", "--revolutions", "0.01"],
        ["tolerance", "--samples", "10"],
        ["design", "--fits", "H8/g7", "--classes", "c", "--require", "rocker_swing <= 60 deg"],
        ["wear", "--hours", "1 h", "--clearance-limit", "+20 um"],
        ["calibrate", "--column", "experiment_printed"],
        ["compare"],
        ["ecs"],
    ],
    ids=lambda command: command[0],
)
def test_every_command_checks_its_out_before_computing(
    command: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A foreign non-empty folder is refused up front (a long study must not run first)."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("precious", encoding="utf-8")
    assert run([*command, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--force" in err and len(err.strip().splitlines()) == 1, err
    assert (out / "notes.txt").read_text(encoding="utf-8") == "precious"


def test_a_parent_nobody_may_write_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A folder no user may create, root included: its parent is a regular file (ENOTDIR),
    so this runs whoever runs the tests (a chmod 0o500 folder does not stop root, and /sys is
    now refused earlier, as a system folder)."""
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder", encoding="utf-8")
    out = blocker / "sub" / "out"
    assert run(["kinematics", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "cannot write the output folder" in err and len(err.strip().splitlines()) == 1, err
    assert blocker.read_text(encoding="utf-8") == "not a folder"


def test_force_refuses_a_folder_outside_the_users_own_work(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--force`` on a foreign folder that is not inside the current folder, the home folder
    or a temp folder (here a stand-in for /var/lib/app: the temp folders moved away) is one
    line, exit 2, the folder whole; the system folders themselves are refused outright."""
    from jointplay.io import output

    home, work, elsewhere = tmp_path / "home", tmp_path / "work", tmp_path / "var" / "app"
    for folder in (home, work, elsewhere):
        folder.mkdir(parents=True)
    (elsewhere / "state.db").write_text("precious", encoding="utf-8")
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(work)
    monkeypatch.setattr(output, "_temp_folders", lambda: [tmp_path / "tmp"])
    assert run(["kinematics", "--no-plots", "--force", "--out", str(elsewhere)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--force replaces such a folder" in err, err
    assert sorted(p.name for p in elsewhere.iterdir()) == ["state.db"]
    for system in ("/var/jointplay-absent", "/opt/jointplay-absent", "/srv/jointplay-absent"):
        assert run(["kinematics", "--no-plots", "--force", "--out", system]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "is a system folder" in err, err


def test_foreign_folder_needs_force(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("precious", encoding="utf-8")
    assert run(["kinematics", "--no-plots", "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert (out / "thesis.tex").read_text(encoding="utf-8") == "precious"
    assert run(["kinematics", "--no-plots", "--force", "--out", str(out)]) == 0
    assert not (out / "thesis.tex").exists()
    assert (out / MARKER).is_file()


def test_out_that_is_a_file_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "file"
    target.write_text("x", encoding="utf-8")
    assert run(["kinematics", "--out", str(target)]) == 2
    assert "not a folder" in capsys.readouterr().err
    assert target.read_text(encoding="utf-8") == "x"


def test_force_never_deletes_an_input_of_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--config proj/my.toml --out proj --force`` used to delete my.toml."""
    project = tmp_path / "proj"
    project.mkdir()
    config = _config(project, "my.toml")
    status = run(["kinematics", "--config", config, "--out", str(project), "--force"])
    err = capsys.readouterr().err
    assert status == 2 and "holds 'my.toml', an input of this run" in err, err
    assert Path(config).is_file()


def test_error_lines_are_cut_to_a_readable_length(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An error that quotes a huge input keeps its start and its end (where the fix is)."""
    limit = "x" * 100_000 + "=:1 rad/s"
    status = run(["tolerance", "--spec-limit", limit, "--out", str(tmp_path / "k")])
    err = capsys.readouterr().err
    assert status == 2 and len(err.splitlines()) == 1, err[:300]
    assert len(err) < 700 and "characters cut" in err, err
    assert "transmission_angle_min" in err, err  # the end of the line: the choices


def test_usage_errors_take_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["simulate", "--revolutions"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert "--revolutions" in err and "--help" in err


def test_no_arguments_shows_the_help(capsys: pytest.CaptureFixture[str]) -> None:
    assert run([]) == 0
    captured = capsys.readouterr()
    assert "Usage" in captured.out and captured.err == ""


def test_outputs_are_checked_before_the_kernels_compile(monkeypatch, tmp_path, capsys) -> None:
    """On a fresh install (no compiled kernels cached) a too-fine --output-step is still one
    error line: the outputs are checked before the compile notice is printed."""
    import jointplay._kernels

    monkeypatch.setattr(jointplay._kernels, "compiled_cache_present", lambda *_: False)
    out = tmp_path / "out"
    assert run(["simulate", "--output-step", "1 ns", "--out", str(out), "--no-progress"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "--output-step" in lines[0], lines
    assert not out.exists()
