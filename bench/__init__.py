"""Benchmarks of pkm against baselines measured in the same run (DESIGN.md section 9).

Run them with ``make bench`` (``python -m bench.run``); docs/benchmarks.md records the latest figures.
"""
