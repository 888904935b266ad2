"""The about page of a rerun recording (``analysis.trace``): what ran and what produced it.

Split from ``analysis.trace`` by job: that module steps the systems and logs their frames; this
one only describes a run, from a ``Recorder``'s public state (its target, steps, tracks,
reference and the code state taken when it started).
"""

import json

from study.metadata import collect, jsonable


def own_scenes(target):
    """{system name: sim.Scene} of the systems that run a scene of their own (the impact
    threshold axis throws the hammer at each policy's own threshold), not the target's."""
    return {
        s.name: s.scene
        for s in target.systems
        if s.scene is not None and s.scene is not target.scene
    }


def provenance(recorder):
    """What produced the recording, as a results file records it (study.metadata.collect: the
    commit and uncommitted changes since the run started, package versions, machine), with
    every scene that ran: a system's own scene was missing (the about page gave sim-extended's
    run sim-paper's 11.86 m/s where it ran at 2.58 m/s), and so was a scene file's path and
    hash (with --out, a hand-edited file looked like its builder's)."""
    t = recorder.target
    parameters = {
        "target": t.label,
        "kind": t.kind,
        "systems": [s.name for s in t.systems],
        "dt": t.dt,
        "steps": recorder.steps,
        "every": recorder.every,
        "arrow_scale": recorder.arrow_scale,
    }
    if t.source:
        parameters["scene_file"] = t.source
    own = own_scenes(t)
    if own:
        parameters["scene_of_system"] = {
            n: {"name": s.name, "params": s.params} for n, s in own.items()
        }
    scenes = list({id(s): s for s in (t.scene, *own.values())}.values())
    return collect(scenes, parameters, script="analysis.trace", started=recorder.started)


def about(recorder):
    """What ran, as markdown: the target, each system's settings (and own scene) or why it did
    not run, and the provenance."""
    t = recorder.target
    reference = recorder.reference.system.name if recorder.reference is not None else "none"
    every = recorder.every
    lines = [
        f"# {t.label}",
        "",
        f"{t.kind}; scene `{t.scene.name}` {json.dumps(jsonable(t.scene.params))}; "
        f"{len(t.scene.bodies)} bodies; dt {t.dt:g} s; {recorder.steps} steps "
        f"(recorded every {every}{' and at the last' if recorder.steps % every else ''}"
        f"); reference {reference}",
        "",
    ]
    if recorder.reference_note:
        lines += [recorder.reference_note, ""]
    own = own_scenes(t)
    for track in recorder.tracks:
        settings = track.runner.settings if track.runner is not None else {}
        lines += [f"## {track.system.name}", ""]
        if track.system.name in own:
            scene = own[track.system.name]
            lines += [f"its own scene `{scene.name}` {json.dumps(jsonable(scene.params))}", ""]
        lines += [
            track.stopped or f"```\n{json.dumps(jsonable(settings), indent=1)}\n```",
            "",
        ]
    text = json.dumps(jsonable(provenance(recorder)), indent=1)
    lines += ["## provenance", "", f"```\n{text}\n```", ""]
    return "\n".join(lines)
