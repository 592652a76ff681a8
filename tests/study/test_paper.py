"""`jointplay paper` on a reduced setting: the report holds every listed quantity."""

from __future__ import annotations

import json
import math

from jointplay.cli import run

LISTED_CLAIMS = [
    ("ECS (Table 5)", "spherical contact K"),
    ("ECS (Table 5)", "spherical contact delta"),
    ("ECS (Table 5)", "spherical contact D"),
    ("ECS (Table 4)", "cylindrical contact K"),
    ("ECS (Table 4)", "cylindrical contact delta"),
    ("ECS (Table 4)", "cylindrical contact D"),
    ("Tolerance stack (spherical ECS)", "coupler's peak angular velocity"),
    ("Tolerance stack (spherical ECS)", "rocker's peak angular velocity"),
    ("Tolerance stack (cylindrical ECS)", "coupler's peak angular velocity"),
    ("Tolerance stack (cylindrical ECS)", "rocker's peak angular velocity"),
    ("Start-up (spherical ECS)", "coupler angular acceleration"),
    ("Start-up (spherical ECS)", "rocker angular acceleration"),
    ("Start-up (spherical ECS)", "rocker angular velocity"),
    ("Start-up (cylindrical ECS)", "rocker angular velocity"),
    ("Joint forces (Table 6, spherical)", "crank-coupler"),
    ("Joint forces (Table 6, spherical)", "coupler-rocker"),
    ("Joint forces (Table 6, spherical)", "rocker-fixed"),
    ("Joint forces (Table 6, cylindrical)", "crank-coupler"),
    ("Joint forces (Table 6, cylindrical)", "coupler-rocker"),
    ("Joint forces (Table 6, cylindrical)", "rocker-fixed"),
    ("Sensitivity", "crank length"),
    ("Sensitivity", "ground length"),
    ("Experiment (Table 7)", "largest |error|"),
]


def test_reduced_paper_study_report(tmp_path) -> None:
    out = tmp_path / "paper"
    args = [
        "paper", "--out", str(out), "--revolutions", "0.03", "--no-corners", "--ecs-source", "paper",
        "--experiment-revolutions", "1", "--workers", "1",
    ]  # fmt: skip
    assert run(args) == 0
    results = json.loads((out / "results.json").read_text())
    claims = results["claims"]
    for section, words in LISTED_CLAIMS:
        matches = [c for c in claims if c["section"] == section and words in c["claim"]]
        assert matches, (section, words)
        assert all(c["ours"] is not None and math.isfinite(c["ours"]) for c in matches), (
            section,
            words,
        )
    simulations = results["simulations"]
    for method in ("ifm-conventional", "rm-conventional"):
        assert simulations[f"method/{method}/-"]["error"] is None
    for method in (
        "ifm-ecs-cylindrical",
        "rm-ecs-cylindrical",
        "ifm-ecs-spherical",
        "rm-ecs-spherical",
    ):
        assert simulations[f"method/{method}/paper"]["peaks"]["omega4"]["value"] > 0
    assert {"corner/++++", "corner/----", "cylindrical/upper", "cylindrical/lower"} <= set(
        simulations
    )
    assert len(results["sensitivities"]) == 4
    assert results["experiment"]["best"]["by_rms_error_percent"]
    html = (out / "report.html").read_text()
    for anchor in ("claims", "mechanism", "ecs", "methods", "tolerance", "experiment", "solver"):
        assert f'id="{anchor}"' in html
    assert html.count("data:image/png;base64,") >= 8  # figures are embedded: the page stands alone
    assert 'src="figures/' not in html
