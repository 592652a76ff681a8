"""``jointplay explore``: the mechanism live in the browser.

:mod:`~jointplay.explore.settings` reads the page's query into settings and a configuration
file; :mod:`~jointplay.explore.engine` simulates them through the command line's readers and
the public API and turns the result into what the page draws; :mod:`~jointplay.explore.app`
is the web application (Starlette) that serves the page, its assets and those two.
"""
