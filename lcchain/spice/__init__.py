"""The only code that starts a circuit simulator or imports PySpice.

It works on netlist text and vector names and knows nothing of chains: the
engines (:data:`~lcchain.spice.engines.ENGINES`: ngspice, gnucap; each a
:class:`~lcchain.spice.engine.Engine`) are found once
(:func:`~lcchain.spice.engines.find_engine`) and run lcchain's netlists
(:func:`~lcchain.spice.engines.run_engine`, :func:`~lcchain.spice.ac.run_ac`): a run is asked for by a
frozen, checked job (:mod:`lcchain.spice.job`) and comes back as one record for every analysis
(:class:`~lcchain.spice.result.RunResult`, its analysis's data a field); ngspice's runner
(:func:`~lcchain.spice.ngspice.runner.run`) reads its raw file and checks a foreign
netlist against the allow-list; ``doctor`` says what is missing.
"""
