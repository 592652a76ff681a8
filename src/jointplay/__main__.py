"""``python -m jointplay`` and the ``jointplay`` console script: the command line.

The console script imports this module, not :mod:`jointplay.cli`: worker processes started
with the ``spawn`` method re-run the script that started their parent, and this keeps that to
``import jointplay`` (the command modules, Typer and Rich, ~0.25 s, are loaded by
:func:`main`, only in the parent).
"""


def main() -> None:
    """Run the command line (:func:`jointplay.cli.main`)."""
    from jointplay.cli import main as command_line

    command_line()


if __name__ == "__main__":
    main()
