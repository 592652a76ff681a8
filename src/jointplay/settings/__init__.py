"""Options and configuration files read into settings: the one reader that both edges use.

The command line (:mod:`jointplay.cli`) and the web app of ``jointplay explore``
(:mod:`jointplay.explore`) turn the same values (an option's string with its unit, or the
``[simulation]`` key of the same name) into the same mechanism, contact model and checks, so
the page simulates what ``jointplay simulate --config`` does. Nothing here knows Typer or
the web: the values arrive as strings, numbers and paths; errors are
:class:`~jointplay.errors.ConfigError` lines that name the option.

- :mod:`~jointplay.settings.mechanism`: the mechanism of ``--preset``/``--config`` with the
  crank-speed, direction, start-angle and gravity overrides; quantity options with units;
- :mod:`~jointplay.settings.simulation`: the contact model of the contact options, the
  numbers and joint list of ``[simulation]``, the revolutions' limit.
"""
