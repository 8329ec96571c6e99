"""What each command does, end to end, as a function with a typed request and a typed result: check the inputs
and outputs, run the simulations (below), then render and write the results (report/).

``cli/`` parses arguments into a request, calls one of these and prints the result; it imports app and core
only, and ``report/`` only renders what was computed and starts no simulator (import-linter contracts say so).
One module per command or family: :mod:`~lcchain.app.design` (design, table, asymptotic),
:mod:`~lcchain.app.netlist` (netlist, reference netlists, examples), :mod:`~lcchain.app.bom`,
:mod:`~lcchain.app.check`, :mod:`~lcchain.app.sensitivity`, :mod:`~lcchain.app.requirements`,
:mod:`~lcchain.app.simulate`, :mod:`~lcchain.app.spectrum`, :mod:`~lcchain.app.scenes` (run),
:mod:`~lcchain.app.sweep`, :mod:`~lcchain.app.batch`, :mod:`~lcchain.app.results`, :mod:`~lcchain.app.figures`,
:mod:`~lcchain.app.validation` (report), :mod:`~lcchain.app.bench`, :mod:`~lcchain.app.doctor`; what they share:
:mod:`~lcchain.app.inputs` (the chain from its options, the files a command writes),
:mod:`~lcchain.app.options` (what a parser offers, read from the registries), :mod:`~lcchain.app.studies`
(where a study's runs execute).
"""
