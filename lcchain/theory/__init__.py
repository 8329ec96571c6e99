"""The paper's theory, exactly: chains, normal modes, arrivals, responses, designs.

numpy and scipy only: nothing here touches files, processes or plots, or
imports PySpice or Dask (import-linter contracts in pyproject.toml).  Every
public entry point computes under a fixed BLAS thread limit
(:mod:`lcchain.core.blas`), so it gives the same bits in any process.
"""
