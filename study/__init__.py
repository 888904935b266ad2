"""freeze2d's study library: everything the experiment scripts (``experiments/``) and the analysis
scripts (``analysis/``) share, and never imports them back (docs/ARCHITECTURE.md §5).

    paths, metadata     where results go; what produced them (commit, versions, CPU), atomic writes
    common              the systems' comparable settings, building a runner, the command line
    peers/              every system behind one Runner interface (sim, pymunk, pybullet, Box2D)
    executor, timing    the sweep executor (resumable, interruptible); the timing protocol
    scenarios           the failure catalogue's scenes, outcomes and classifiers
    protocols, cost_fit the freeze study's measurement protocols; the per-body cost fit
    extremes/           the extremes table's axes, scenes, judge, rules and runs
    overlap, filmstrip  polygon overlap; filmstrip frames of a run
    targets             a scene, scenario, scene file or table cell to replay (the recordings)
"""
