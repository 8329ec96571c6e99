"""Studies: plans of many runs, the executors that run them, and what they measure.

The accuracy bench lives here; sweeps, Monte Carlo and batches of netlists
(process pool, Dask) join it.  Dask is imported here only.
"""
