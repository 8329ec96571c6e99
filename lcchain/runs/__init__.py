"""One unit of work: a frozen description of a run, its execution, its record.

Every orchestrator (simulate, scenes, the accuracy bench, studies) builds
:class:`~lcchain.runs.spec.RunSpec` values and hands them to
:func:`~lcchain.runs.execute.execute`; none edits netlist text or talks to
ngspice itself.  Specs and records pickle, so the same run can execute here,
in a process pool or on a Dask worker.
"""
