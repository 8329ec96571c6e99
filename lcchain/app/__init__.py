"""What a command does, end to end: run the simulations (below), then render and write the results (report/).

``cli/`` parses arguments and calls these; ``report/`` only renders what was computed and starts no simulator
(an import-linter contract says so).  Public entry points: :func:`lcchain.app.scenes.run_scene`,
:func:`lcchain.app.validation.make_report`.
"""
