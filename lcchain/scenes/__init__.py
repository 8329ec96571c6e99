"""Scenes: one experiment written down in TOML, checked, turned into runs, run.

``schema`` holds the typed frozen objects (no physics), ``load`` reads files
into them, ``plan`` turns a scene into chains, netlists and run specs, and
``run`` executes them and writes up the report (files are written by
:mod:`lcchain.report.scenes`).
"""
