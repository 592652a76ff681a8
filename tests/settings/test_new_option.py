"""Adding a contact option takes its declaration and its field, two source files
(docs/contact.md, "Adding a contact option"; issue 38, "each setting declared once").

The option below is defined here only: a ``squeeze`` factor on a throwaway subclass of
:class:`~jointplay.dynamics.setup.ContactModel` (its field, checked in ``__post_init__``: what
``dynamics/setup.py`` would hold) and one :class:`~jointplay.dynamics.declared.Setting` (what
``dynamics/declared.py`` would hold). Declared before the command line is imported, it must
be an option of every simulating command, with its help and panel; a key of the
``[simulation]`` table, read as a number; reach the contact model from either; and its
errors must name the option, through the readers and commands as they are.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import typer

import jointplay
from jointplay.cli._app import app
from jointplay.cli._panels import option_panel
from jointplay.cli._simulation import SETTING_OPTIONS
from jointplay.dynamics import setup
from jointplay.dynamics.declared import CONTACT_PANEL, CONTACT_SETTINGS, RUN_PANEL, RUN_SETTINGS
from jointplay.dynamics.settings import RunSettings
from jointplay.dynamics.simulate import SolverOptions, Start
from jointplay.io.config import SIMULATION_KEYS

#: Every command that simulates the clearance joints: each takes the contact options.
COMMANDS = ("simulate", "animate", "tolerance", "design", "wear", "life")
OWNERS = {
    "settings": setup.ContactSettings,
    "friction": setup.FrictionSettings,
    "model": setup.ContactModel,
    "run": RunSettings,
    "start": Start,
    "solver": SolverOptions,
}

NEW_OPTION = r"""
import dataclasses, json, sys
from pathlib import Path

from jointplay.dynamics import declared, setup
from jointplay.errors import SettingError

# dynamics/setup.py: the new field on its record, checked where the record is built.
@dataclasses.dataclass(frozen=True)
class SqueezedContact(setup.ContactModel):
    squeeze: float = 1.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if not self.squeeze > 0:
            raise SettingError("{squeeze} must be > 0, got {got!r}", got=self.squeeze)

setup.ContactModel = SqueezedContact

# dynamics/declared.py: its declaration.
HELP = "Squeeze-film factor on the film damping (test only)."
declared.CONTACT_SETTINGS = (
    *declared.CONTACT_SETTINGS,
    declared.Setting("squeeze", "--squeeze", "squeeze", "model", HELP, kind=float),
)

# Nothing else is edited: the command line, the readers and the studies as they are.
import typer
from jointplay.cli import run
from jointplay.cli._app import app
from jointplay.cli._panels import option_panel
from jointplay.io.config import load_preset, simulation_settings
from jointplay.settings.simulation import contact_from_options

folder = Path(sys.argv[1])
click_app = typer.main.get_command(app)
for name in json.loads(sys.argv[2]):
    options = {o: p for p in click_app.commands[name].params for o in p.opts}
    assert "--squeeze" in options, f"{name} does not offer --squeeze"
    option = options["--squeeze"]
    assert option.help == HELP and option.rich_help_panel == "Contact", name
    assert option.type_descriptor.annotation is float, name  # a number, as declared

config = folder / "squeezed.toml"
config.write_text('[simulation]\nsqueeze = 2.5\n', encoding="utf-8")
assert simulation_settings(config) == {"squeeze": 2.5}
mechanism = load_preset("paper-fourbar")
assert contact_from_options(config, mechanism).squeeze == 2.5  # the [simulation] key
assert contact_from_options(config, mechanism, squeeze=4.0).squeeze == 4.0  # the option over it
assert contact_from_options(None, mechanism).squeeze == 1.0  # not given: the field's default
assert contact_from_options(None, mechanism, method="ifm-conventional", squeeze=3.0).squeeze == 3.0

wordy = folder / "wordy.toml"
wordy.write_text('[simulation]\nsqueeze = "lots"\n', encoding="utf-8")
assert run(["simulate", "--config", str(wordy), "--out", str(folder / "a")]) == 2
assert run(["simulate", "--squeeze", "0", "--out", str(folder / "b")]) == 2
assert run(["tolerance", "--squeeze", "2", "--out", str(folder / "c")]) == 2
"""


def test_a_new_contact_option_is_its_declaration_and_its_field(tmp_path: Path) -> None:
    import json

    done = subprocess.run(
        [sys.executable, "-c", NEW_OPTION, str(tmp_path), json.dumps(COMMANDS)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    errors = [line for line in done.stderr.splitlines() if line.startswith("jointplay: error")]
    assert errors == [
        f"jointplay: error: {tmp_path / 'wordy.toml'}: simulation.squeeze must be a number, "
        "got 'lots'",
        "jointplay: error: --squeeze must be > 0, got 0.0",
        "jointplay: error: contact options apply to --responses dynamic or running only",
    ], done.stderr


def test_every_declared_setting_is_a_field_an_option_and_a_key() -> None:
    """What the new option relies on holds for the built-in ones: each declaration names a
    field of its record, is an option of every simulating command with its declared help,
    kind and panel, a ``[simulation]`` key, and the option errors name its setting by."""
    click_app = typer.main.get_command(app)
    commands = {
        name: {o: p for p in click_app.commands[name].params for o in p.opts}  # type: ignore[attr-defined]
        for name in COMMANDS
    }
    for declared in CONTACT_SETTINGS:
        assert declared.key in SIMULATION_KEYS, declared.key
        assert SETTING_OPTIONS[declared.name] == declared.option, declared.key
        if declared.owner != "method":
            fields = {f.name for f in setup.dataclasses.fields(OWNERS[declared.owner])}
            assert declared.field in fields, declared.key
        for name, options in commands.items():
            option = "--paper-method" if (name, declared.key) == ("tolerance", "method") else None
            shown = options.get(option or declared.option)
            if not declared.offered:
                assert shown is None, (name, declared.option)
                continue
            assert shown is not None, (name, declared.option)
            assert shown.rich_help_panel == CONTACT_PANEL, (name, declared.option)
            assert shown.type_descriptor.annotation is declared.kind, declared.key
            if option is None:
                assert shown.help == declared.help, (name, declared.option)


def test_every_run_setting_is_a_field_a_key_and_the_option_of_simulate() -> None:
    """The run's declared settings (``--start``, ``--rtol``, ...): a field of their record, a
    ``[simulation]`` key, the option errors name them by, and ``simulate``'s option with the
    declared help, kind and panel (``--revolutions`` and ``--settle`` read as simulate's own
    there)."""
    click_app = typer.main.get_command(app)
    options = {o: p for p in click_app.commands["simulate"].params for o in p.opts}  # type: ignore[attr-defined]
    for declared in RUN_SETTINGS:
        assert declared.key in SIMULATION_KEYS, declared.key
        assert SETTING_OPTIONS[declared.name] == declared.option, declared.key
        fields = {f.name for f in setup.dataclasses.fields(OWNERS[declared.owner])}
        assert declared.field in fields, declared.key
        shown = options[declared.option]
        assert option_panel(shown) == RUN_PANEL, declared.option
        assert shown.type_descriptor.annotation is declared.kind, declared.key
        if declared.key not in ("revolutions", "settle"):
            assert shown.help == declared.help, declared.option


def test_no_command_spells_a_contact_option_of_its_own() -> None:
    """The simulating commands' contact options are spelt in their declarations only: a
    command that listed one again (an option, a dict key to its name) would be a second
    place to edit. Options that other commands also offer for their own purposes
    (``compare --method``, ``ecs --restitution``, ...) are left out."""
    click_app = typer.main.get_command(app)
    elsewhere = {
        option
        for name, command in click_app.commands.items()  # type: ignore[attr-defined]
        if name not in COMMANDS
        for param in command.params
        for option in param.opts
    }
    own = {s.option for s in CONTACT_SETTINGS} - elsewhere - {"--method"}
    assert {"--k", "--cmax", "--friction-law", "--film-damping"} <= own
    source = Path(jointplay.__file__).parent
    spelt: dict[str, list[str]] = {}
    for path in sorted(source.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and node.value in own:
                spelt.setdefault(str(node.value), []).append(str(path.relative_to(source)))
    assert spelt == {option: ["dynamics/declared.py"] for option in own}
