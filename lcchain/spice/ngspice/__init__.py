"""ngspice, lcchain's default engine: its transports, its workers and its raw-file reader.

- :mod:`~lcchain.spice.ngspice.engine`: :class:`~lcchain.spice.ngspice.engine.Ngspice`, the
  :class:`~lcchain.spice.engine.Engine` (one line in :data:`lcchain.spice.engines.ENGINES`).
- :mod:`~lcchain.spice.ngspice.runner`: :func:`~lcchain.spice.ngspice.runner.run`, the entry point of a
  transient (the allow-list and the sandbox for netlists lcchain did not write), over the transports
  (:data:`~lcchain.spice.ngspice.transports.TRANSPORT_RUNS`, a registry of
  :class:`~lcchain.spice.ngspice.transports.NgspiceTransport`: each one's run and find), and ``run_plot`` for the
  other analyses; :mod:`~lcchain.spice.ngspice.find` chooses a transport, :mod:`~lcchain.spice.ngspice.locate`
  says where ngspice is and its version.
- The transports: :mod:`~lcchain.spice.ngspice.batch` (``ngspice -b``), :mod:`~lcchain.spice.ngspice.shared`
  (the shared library in a child per run, :mod:`~lcchain.spice.ngspice.shared_worker`) and
  :mod:`~lcchain.spice.ngspice.warm` (the shared library in long-lived workers,
  :mod:`~lcchain.spice.ngspice.warm_worker`); :mod:`~lcchain.spice.ngspice.place` says where a child runs.
- :mod:`~lcchain.spice.ngspice.raw`: the raw-file reader.

The engine-neutral process code (process groups, timeouts, pidfd waits, limits) is
:mod:`lcchain.spice.processes`, which gnucap uses too.  This package's ``__init__`` imports nothing, so that
:mod:`lcchain.spice.simulator` (which finds ngspice's transports) can use the shared worker's launcher.
"""
