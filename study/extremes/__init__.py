"""The extremes table's library (experiments/table_extremes.py is the script that sweeps it):
axes, scenes, geometry, judge, rules, threshold, runs, record. See the script's docstring."""
