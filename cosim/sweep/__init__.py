"""Scenario sweeps and Monte Carlo on Dask distributed (``crd sweep``).

The flow: a sweep file (:mod:`.spec`) -> the design of axis values
(:mod:`.design`) -> one resolved scenario per run with its key and seed
(:mod:`.plan`, key paths by :mod:`.keypath`) -> Dask tasks (:mod:`.runner`,
worker side :mod:`.task`) -> ``results.parquet`` (:mod:`.table`) -> heat maps
(:mod:`.maps`) and ``report.md`` (:mod:`.report`). :func:`.session.run_sweep`
ties them together.
"""
