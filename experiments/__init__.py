"""freeze2d's experiments: one script per figure or table, each writing results/data/<name>.csv
plus <name>.json metadata (see docs/ARCHITECTURE.md §5). Run as ``python -m experiments.<name>``.
A script imports ``sim`` and the study library (``study``) only, never another script."""
