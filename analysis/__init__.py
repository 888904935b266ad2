"""Figures, tables and rerun recordings drawn from ``results/data`` (one script per figure).

Built by the study issue: ``analysis`` reads only ``results/data`` and writes
``paper/figures/<name>.svg`` and ``paper/generated/<name>.csv``; it never runs a simulation.
"""
