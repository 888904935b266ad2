"""A rerun recording (``.rrd``) of any run, every named system side by side, to inspect frame by
frame where their outcomes part.

    python -m analysis.trace NAME [--systems A,B,...] [--steps N] [--every K] [--out PATH]
    python -m analysis.trace --table table_failures [--out-dir DIR]     (one file per row)
    python -m analysis.trace --list                                     (what NAME can be)
    make trace SCENE=slope_creep SYSTEMS=sim-off,sim-extended,pymunk-sleep
    make trace CELL=table_extremes/dt/0.03333
    rerun results/recordings/<name>.rrd                                (opens it)

NAME is a scene builder (pyramid), a failure-catalogue scenario (slope_creep), a scene file
(path/to/scene.toml) or a table cell (table_failures/<scenario>, table_extremes/<axis>/<value>):
study.targets resolves it, running a cell exactly as its table does. Every system starts
from the same scene and is stepped in lockstep; the first one named is the *reference* (if it
cannot run, e.g. Box2D refusing dt 0.5 s, the first that can, and the events and stderr say so).

What the recording holds, on the timelines ``step`` (the run's step count) and ``time``
(simulated seconds), one entity path per system (<s>: the system's name, e.g. ``sim-extended``,
``sim-off_no-presolve``):

  systems/<s>/bodies        every body as a closed outline, coloured by its state (sim: FREE,
                            VERTICAL_STABLE, ROTATION_STABLE, SLEEPING; a peer's bodies are FREE
                            awake and SLEEPING asleep), frozen or asleep bodies at half brightness;
                            under sim-extended each awake body labelled with the rest-test stage
                            that keeps it awake (``World.why_awake``: "sliding", "deep", ...)
  systems/<s>/static        the floor and static bodies (static: logged once)
  systems/<s>/contacts      the contact points of the step (each engine's own, runner.contacts)
  systems/<s>/impulses      normal impulses as arrows, ``--arrow-scale`` m per N s, each the
                            impulse on the pair's dynamic body of higher index (the floor and
                            static bodies rank lowest; study.peers.impulse_vectors): the same
                            convention in every engine, up into a resting box
  events/<s>                freeze/wake events (sim: World.events with their cause; a peer: a
                            body falling asleep or waking), a system not run and why, a system
                            that stopped (an error, a non-finite state)
  timeline/awake/<s>        bodies the system still solves
  timeline/kinetic_energy/<s>    J (the same formula for every system: translational + rotational)
  timeline/step_ms/<s>      wall time of the system's step, ms (stepped one system after the
                            other in this process: for looking, not a benchmark; see
                            experiments/bench_* for timings)
  timeline/divergence_m/<s>      largest centre distance to the reference's same body, m
  timeline/divergence_rad/<s>    largest angle difference to it (modulo 2 pi), rad
  about                     what ran: the target, the steps run, every system's settings, and
                            the provenance a results file records (study.metadata.collect:
                            commit, uncommitted changes, package versions, machine, date)

A blueprint is written with the recording, so the viewer opens on the scene views side by side
with the timelines and the event log below. A long run is recorded every K steps (``--every``;
default: at most MAX_FRAMES frames), and at its last step whatever K is, the step timeline
keeping the true step numbers.

The file is written as <out>.partial.rrd beside <out> and renamed to <out> when the run ends, so
<out> is only ever a whole recording: an interrupted or failed run leaves the old <out> as it
was, and what it recorded so far in the partial file (named on stderr; exit status 130 on
Ctrl-C). Without --out the file is results/recordings/<name>.rrd, the name saying what
distinguishes the run (study.targets.Target.file_stem: the builder's size, a dt other than
1/60, the systems when not the default ones, --steps, --every), so that different runs never
overwrite each other: ``pyramid --size 40 --systems pymunk`` -> ``pyramid__size40__pymunk.rrd``.
"""

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

import sim
from analysis import trace_about
from analysis.style import STATE_RGB, system_style
from study import scenarios, targets
from study.extremes.geometry import Shapes
from study.metadata import code_state
from study.paths import RECORDINGS, creatable, partial_path, writable
from study.peers import impulse_vectors, sim_world
from sim.files import write_text_atomically
from study.cli import first_paragraph, positive_float

#: state -> RGB (FREE, VERTICAL_STABLE, ROTATION_STABLE, SLEEPING): the figures' colours
STATE_COLORS = np.array(STATE_RGB, np.uint8)
#: a frozen (sim) or asleep (peer) body is drawn at this fraction of its state's colour
FROZEN_SHADE = 0.5
MAX_FRAMES = 2000  # default: record every ceil(steps / MAX_FRAMES) steps
TABLES = ("table_failures",)  # --table: every row recorded (the extremes cells: by name)


def body_colors(states, frozen):
    """(N,3) uint8 RGB of bodies in ``states`` (sim.State values), ``frozen`` (N,) bool darker."""
    colors = STATE_COLORS[np.asarray(states, dtype=int)].astype(float)
    colors[np.asarray(frozen, dtype=bool)] *= FROZEN_SHADE
    return colors.astype(np.uint8)


def _rgb(system):
    hex_color = system_style(system.split(" (")[0])["color"].lstrip("#")
    return [int(hex_color[k : k + 2], 16) for k in (0, 2, 4)]


class Track:
    """One system of a recording: its runner (None when not run), its geometry, what was logged
    of it so far, and why it stopped (empty while it runs)."""

    def __init__(self, system, target):
        self.system = system
        self.path = targets.slug(system.name)
        self.scene = system.scene or target.scene
        self.shapes = Shapes(self.scene)
        self.runner = None
        self.stopped = system.not_run and f"not run: {system.not_run}"
        self.n_events = 0
        self.asleep = np.zeros(len(self.scene.bodies), dtype=bool)
        self.pose = None
        if not self.stopped:
            try:
                self.runner = system.build(target.scene, target.dt)
            except ValueError as exc:  # the system refuses the scene: a result, logged
                self.stopped = f"not run: refused ({exc})"

    @property
    def world(self):
        """The sim.World of a sim system (its states, events), None for a peer."""
        return sim_world(self.runner)

    def close(self):
        if self.runner is not None:
            self.runner.close()


class Recorder:
    """Writes the frames of a target's tracks to one rerun recording."""

    def __init__(self, target, path, steps, every, arrow_scale):
        self.target, self.steps, self.every = target, steps, every
        self.arrow_scale, self.reached = arrow_scale, 0  # reached: the last step recorded
        self.started = code_state()  # the code that runs (the about page's provenance)
        self.tracks = [Track(s, target) for s in target.systems]
        seen = {}
        for t in self.tracks:  # a system named twice: "sim-off", "sim-off_2"
            seen[t.path] = seen.get(t.path, 0) + 1
            if seen[t.path] > 1:
                t.path = f"{t.path}_{seen[t.path]}"
        # the divergence's reference: the first system named, or else the first that runs (a
        # refused first system left every divergence unlogged, and nothing said why)
        self.reference = next((t for t in self.tracks if not t.stopped), None)
        first = self.tracks[0]
        self.reference_note = ""
        if self.reference is None:
            self.reference_note = "no system runs: no divergence is recorded"
        elif self.reference is not first:
            self.reference_note = (
                f"the reference {first.system.name} is {first.stopped}: divergence is measured "
                f"against {self.reference.system.name}, the first system that runs"
            )
        self.rec = rr.RecordingStream(f"freeze2d-{target.stem}")
        self.rec.save(str(path), default_blueprint=self.blueprint())
        self._static()

    # ---- layout and what does not change ---------------------------------------------------
    def blueprint(self):
        """The scene views side by side (a grid beyond four), the timelines and events below."""
        views = [
            rrb.Spatial2DView(
                origin=f"systems/{t.path}",
                name=t.system.name if t.path == targets.slug(t.system.name) else t.path,
            )
            for t in self.tracks
        ]
        scenes = rrb.Horizontal(*views) if len(views) <= 4 else rrb.Grid(*views, grid_columns=4)
        reference = self.reference.system.name if self.reference is not None else "none"
        series = rrb.Horizontal(
            rrb.TimeSeriesView(
                origin="timeline/divergence_m", name=f"largest position error vs {reference}, m"
            ),
            rrb.TimeSeriesView(origin="timeline/awake", name="awake bodies"),
            rrb.TimeSeriesView(origin="timeline/kinetic_energy", name="kinetic energy, J"),
            rrb.TimeSeriesView(origin="timeline/step_ms", name="step wall time, ms"),
        )
        below = rrb.Horizontal(
            rrb.TextLogView(origin="events", name="events"),
            rrb.TextDocumentView(origin="about", name="about"),
            column_shares=[2, 1],
        )
        return rrb.Blueprint(
            rrb.Vertical(scenes, series, below, row_shares=[3, 2, 1]),
            rrb.TimePanel(timeline="step"),
            collapse_panels=True,
        )

    def _static(self):
        rec, scene = self.rec, self.target.scene
        for t in self.tracks:
            rgb = _rgb(t.system.name)
            for quantity in (
                "awake",
                "kinetic_energy",
                "step_ms",
                "divergence_m",
                "divergence_rad",
            ):
                rec.log(
                    f"timeline/{quantity}/{t.path}",
                    rr.SeriesLines(colors=[rgb], names=[t.system.name]),
                    static=True,
                )
            strips = [np.vstack([v, v[:1]]) for v in t.shapes.statics]
            if scene.floor_y is not None:  # wider than the scene by 10 m each side
                x = np.array([b.position[0] for b in t.scene.bodies] + [0.0])
                strips.append(
                    np.array([(x.min() - 10.0, scene.floor_y), (x.max() + 10.0, scene.floor_y)])
                )
            if strips:
                rec.log(
                    f"systems/{t.path}/static",
                    rr.LineStrips2D(strips, colors=[(0, 0, 0)] * len(strips)),
                    static=True,
                )
        self._about()

    def _about(self):
        rec = self.rec
        rec.log(
            "about", rr.TextDocument(self.about(), media_type=rr.MediaType.MARKDOWN), static=True
        )

    def provenance(self):
        """What produced the recording (``analysis.trace_about.provenance``)."""
        return trace_about.provenance(self)

    def about(self):
        """The about page, markdown (``analysis.trace_about.about``)."""
        return trace_about.about(self)

    # ---- frames ------------------------------------------------------------------------------
    def frame(self, step, advance):
        """Step every running track ``advance`` steps and log it at ``step`` (0: the start
        state, ``advance`` 0)."""
        rec = self.rec
        rec.set_time("step", sequence=step)
        rec.set_time("time", duration=step * self.target.dt)
        reference = None
        for t in self.tracks:
            if t.stopped:
                continue
            if advance > 0:
                t0 = time.perf_counter()
                try:
                    t.runner.step(advance)
                except Exception as exc:  # the system's failure is a result
                    self._stop(t, step, f"{type(exc).__name__}: {exc}")
                    continue
                per_step = rr.Scalars(1e3 * (time.perf_counter() - t0) / advance)
                rec.log(f"timeline/step_ms/{t.path}", per_step)
            try:  # a peer refuses to hand out any non-finite observable (study.peers.guards)
                positions, angles = t.runner.positions, t.runner.angles
                if not (np.isfinite(positions).all() and np.isfinite(angles).all()):
                    raise sim.SimulationError(t.system.name)  # a sim.World hands NaN out
                t.pose = positions, angles
                self._bodies(t, positions, angles)
                self._events(t, step, advance)
                if t is self.reference:  # tracks before it do not run
                    reference = t.pose
                self._scalars(t, reference)
            except sim.SimulationError:
                self._stop(t, step, "non-finite state")

    def _bodies(self, t, positions, angles):
        rec = self.rec
        w = t.shapes.world(positions, angles)  # (N,K,2) m
        strips = np.concatenate([w, w[:, :1]], axis=1)  # closed outlines
        labels = None
        if t.world is not None:
            colors = body_colors(t.world.states, t.world.frozen)
            if t.world.freeze == "extended":  # what keeps each awake body awake, frame by frame
                labels = t.world.why_awake().tolist()
        else:
            asleep = np.asarray(t.runner.asleep, dtype=bool)
            colors = body_colors(np.where(asleep, sim.State.SLEEPING, sim.State.FREE), asleep)
        rec.log(f"systems/{t.path}/bodies", rr.LineStrips2D(strips, colors=colors, labels=labels))
        contacts = getattr(t.runner, "contacts", None)
        if contacts is not None:
            c = contacts()
            rec.log(f"systems/{t.path}/contacts", rr.Points2D(c["point"], radii=0.02))
            rec.log(
                f"systems/{t.path}/impulses",
                rr.Arrows2D(
                    origins=c["point"],
                    vectors=impulse_vectors(c, len(t.scene.bodies)) * self.arrow_scale,
                ),
            )

    def _events(self, t, step, advance):
        """Log the events of the steps since the last frame: sim's at the steps they happened
        (with --every K they sat at the frame's step, their text saying another), a peer's as
        seen at this frame ("by step N" when frames are more than a step apart: only the
        change since the last frame is known)."""
        rec = self.rec
        world = t.world
        if world is not None:
            for at, body, before, after, cause in world.events[t.n_events :]:
                rec.set_time("step", sequence=at)
                rec.set_time("time", duration=at * self.target.dt)
                rec.log(
                    f"events/{t.path}",
                    rr.TextLog(
                        f"{t.system.name} step {at}: {t.scene.body_name(body)} {before.name} -> "
                        f"{after.name} ({cause})"
                    ),
                )
            rec.set_time("step", sequence=step)  # back to the frame's
            rec.set_time("time", duration=step * self.target.dt)
            t.n_events = len(world.events)
            return
        when = f"step {step}" if advance <= 1 else f"by step {step} (since step {step - advance})"
        asleep = np.asarray(t.runner.asleep, dtype=bool)
        for body in np.flatnonzero(asleep != t.asleep):
            what = "fell asleep" if asleep[body] else "woke"
            rec.log(
                f"events/{t.path}",
                rr.TextLog(f"{t.system.name} {when}: {t.scene.body_name(int(body))} {what}"),
            )
        t.asleep = asleep

    def _scalars(self, t, reference):
        rec = self.rec
        awake = int((~np.asarray(t.runner.asleep, dtype=bool)).sum())
        positions, angles = t.pose
        kinetic, _ = t.shapes.energy(positions, t.runner.velocities, t.runner.angular_velocities)
        rec.log(f"timeline/awake/{t.path}", rr.Scalars(float(awake)))
        rec.log(f"timeline/kinetic_energy/{t.path}", rr.Scalars(kinetic))
        if reference is not None:
            d = np.hypot(*(positions - reference[0]).T)
            a = np.abs(scenarios.wrap(angles - reference[1]))
            rec.log(f"timeline/divergence_m/{t.path}", rr.Scalars(float(d.max())))
            rec.log(f"timeline/divergence_rad/{t.path}", rr.Scalars(float(a.max())))

    def _stop(self, t, step, why):
        t.stopped = f"stopped at step {step}: {why}"
        self.rec.log(
            f"events/{t.path}",
            rr.TextLog(f"{t.system.name} {t.stopped}", level=rr.TextLogLevel.ERROR),
        )
        print(f"{t.system.name}: {t.stopped}", file=sys.stderr)
        if t is self.reference:
            self._note(f"the reference {t.system.name} stopped: no divergence after step {step}")

    def _note(self, text):
        """A message about the whole recording: in its events and on stderr."""
        self.rec.log("events/recording", rr.TextLog(text, level=rr.TextLogLevel.WARN))
        print(f"{self.target.label}: {text}", file=sys.stderr)

    def frame_steps(self):
        """The steps recorded: 0, every K steps, and the last (steps // K frames stopped short
        of it: 100 steps every 7 ended at step 98)."""
        return sorted(set(range(0, self.steps + 1, self.every)) | {self.steps})

    def run(self, progress=None):
        """Step and record every frame; returns the tracks (``close`` then writes the file
        out and closes their runners, after an exception too)."""
        self.rec.set_time("step", sequence=0)
        self.rec.set_time("time", duration=0.0)
        for t in self.tracks:
            if t.stopped:
                self.rec.log(
                    f"events/{t.path}",
                    rr.TextLog(f"{t.system.name} {t.stopped}", level=rr.TextLogLevel.WARN),
                )
                print(f"{t.system.name}: {t.stopped}", file=sys.stderr)
        if self.reference_note:
            self._note(self.reference_note)
        steps = self.frame_steps()
        frames = len(steps) - 1
        for k, step in enumerate(steps):
            self.reached = step
            self.frame(step, step - steps[k - 1] if k else 0)
            if progress is not None:
                progress(k, frames)
        if self.provenance()["code_changed_during_run"] is True:  # say so on the about page
            self._about()
        return self.tracks

    def close(self):
        """Write out what was logged, close the file and the runners."""
        self.rec.flush()
        self.rec.disconnect()
        for t in self.tracks:
            t.close()


class Interrupted(Exception):
    """A recording that did not run to its end; the message is one line for the user."""


def record(target, path, steps=None, every=None, arrow_scale=0.5, progress=None):
    """Record ``target`` (study.targets.Target) for ``steps`` steps (default its own) to
    ``path``, one frame every ``every`` steps (default: at most MAX_FRAMES frames) and one at
    the last step. Returns the tracks (``.runner`` closed; ``.stopped``: why a system did not
    run to the end, or "").

    Written to ``partial_path(path)`` and renamed to ``path`` at the end: a run stopped by an
    exception (Ctrl-C included) leaves ``path`` as it was and the frames so far in the partial
    file, and raises ``Interrupted`` (from the exception) saying both."""
    steps = target.steps if steps is None else steps
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise ValueError(f"steps must be an integer >= 1, got {steps!r}")
    if every is None:
        every = max(1, math.ceil(steps / MAX_FRAMES))
    if isinstance(every, bool) or not isinstance(every, int) or not 1 <= every <= steps:
        raise ValueError(f"every must be an integer in [1, steps={steps}], got {every!r}")
    writable(path)
    partial = partial_path(path)
    recorder = Recorder(target, partial, steps, every, arrow_scale)
    try:
        tracks = recorder.run(progress)
    except BaseException as exc:  # Ctrl-C included
        recorder.close()
        what = "interrupted" if isinstance(exc, KeyboardInterrupt) else f"failed ({exc!r})"
        kept = f"{path} left as it was" if Path(path).exists() else f"{path} not written"
        raise Interrupted(
            f"{target.label} {what} at step {recorder.reached} of {steps}: {kept}; the steps "
            f"recorded so far are in {partial}"
        ) from exc
    recorder.close()
    os.replace(partial, path)  # whole, or not at all: the old file stays until this
    return tracks


def _progress(label):
    start = time.perf_counter()

    live = sys.stderr.isatty()  # a terminal: one line, rewritten; a log: lines
    start_of_line = "\r" if live else ""

    def show(k, frames):
        if k == frames or (k and k % (100 if live else 1000) == 0):
            print(
                f"{start_of_line}{label}: frame {k}/{frames}, {time.perf_counter() - start:.1f} s",
                end="\n" if k == frames or not live else "",
                file=sys.stderr,
                flush=True,
            )

    return show


def _record_one(name, args):
    target = targets.resolve(name, systems=args.systems, size=args.size, dt=args.dt)
    stem = target.file_stem(steps=args.steps, every=args.every)
    path = Path(args.out) if args.out else RECORDINGS / f"{stem}.rrd"
    record(
        target,
        path,
        steps=args.steps,
        every=args.every,
        arrow_scale=args.arrow_scale,
        progress=_progress(target.label),
    )
    size = path.stat().st_size
    print(f"wrote {path} ({size / 1e6:.1f} MB; open it with: rerun {path})")
    return path


def _record_table(args):
    """Every row of ``args.table`` into ``--out-dir``, then its index.txt (the Make target:
    written last, so an interrupted run is redone): one line per file with its size."""
    changed = [o for o in ("systems", "steps", "every") if getattr(args, o) is not None]
    if changed and args.out_dir is None:  # the default folder holds the rows make keeps
        raise ValueError(
            f"--table {args.table} with --{', --'.join(changed)} records rows that are not the "
            f"table's whole rows: give --out-dir DIR (the default, {RECORDINGS / args.table}, "
            f"holds the rows `make reproduce` writes and keeps)"
        )
    folder = creatable(args.out_dir or RECORDINGS / args.table)
    written = []
    for scenario in scenarios.SCENARIOS:
        args.out = str(folder / f"{scenario}.rrd")
        written.append(_record_one(f"{args.table}/{scenario}", args))
    total = sum(p.stat().st_size for p in written)
    systems = ", ".join(args.systems) if args.systems else "every system of the table"
    lines = [
        f"# {args.table}: one recording per row, {systems}"
        f"{f', {args.steps} steps' if args.steps else ''}"
        f"{f', every {args.every}' if args.every else ''} "
        f"(python -m analysis.trace {args.table}/<row>); {total / 1e6:.1f} MB in all"
    ]
    lines += [f"{p.name}\t{p.stat().st_size / 1e6:.2f} MB" for p in written]
    write_text_atomically(folder / "index.txt", "\n".join(lines) + "\n")
    print(f"{args.table}: {len(written)} recordings, {total / 1e6:.1f} MB in {folder}")
    return written


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python -m analysis.trace",
        description=first_paragraph(__doc__),
        epilog=targets.available(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "name",
        nargs="?",
        help="a scene builder, scenario, scene file (.toml) or table cell (see below)",
    )
    parser.add_argument(
        "--systems",
        default=None,
        help="comma-separated systems, the first the reference (default: a "
        "cell's table's systems, else " + ",".join(targets.DEFAULT_SYSTEMS) + ")",
    )
    parser.add_argument(
        "--size",
        type=int,
        default=None,
        help="a builder's body count: "
        + ", ".join(f"{b} {p}" for b, p in targets.SIZE_PARAMETERS.items())
        + " (no other builder has one)",
    )
    parser.add_argument(
        "--dt",
        type=float,
        default=None,
        help="s per step of a scene (default 1/60; a cell runs at its table's)",
    )
    parser.add_argument(
        "--steps",
        type=int,
        default=None,
        help=f"steps to record (default: a scenario's or cell's duration, else "
        f"{targets.DEFAULT_STEPS})",
    )
    parser.add_argument(
        "--every",
        type=int,
        default=None,
        help=f"record every K steps (default: at most {MAX_FRAMES} frames)",
    )
    parser.add_argument(
        "--out",
        default=None,
        help="output .rrd (default results/recordings/<name>.rrd, the name saying what "
        "distinguishes the run: size, dt, systems, steps, every)",
    )
    parser.add_argument(
        "--table",
        choices=TABLES,
        default=None,
        help="record every row of a table, one file each, into --out-dir",
    )
    parser.add_argument(
        "--out-dir", default=None, help="folder for --table (default results/recordings/<table>)"
    )
    parser.add_argument("--arrow-scale", type=positive_float, default=0.5, help="m per N s")
    parser.add_argument("--list", action="store_true", help="print what NAME can be and exit")
    args = parser.parse_args(argv)
    if args.list:
        print(targets.available())
        return None
    raw_systems = args.systems
    if args.systems is not None:
        args.systems = [s.strip() for s in args.systems.split(",") if s.strip()]
        if not args.systems:  # "," fell back to the default systems
            parser.error(f"--systems {raw_systems!r} names no system")
    # --out with --table, or --out-dir without it, was silently ignored
    ignored = (args.table and args.out) or (args.out_dir and not args.table)
    if (args.name is None) == (args.table is None) or ignored:
        parser.error("give a NAME [--out FILE] or --table [--out-dir DIR]; --list shows the names")
    try:
        if args.table is None:
            return _record_one(args.name, args)
        return _record_table(args)
    except ValueError as exc:
        parser.exit(2, f"python -m analysis.trace: error: {exc}\n")
    except Interrupted as exc:  # Ctrl-C: one line, status 130 as the shell's; a bug: traceback
        if not isinstance(exc.__cause__, KeyboardInterrupt):
            raise
        parser.exit(130, f"python -m analysis.trace: {exc}\n")
    except KeyboardInterrupt:  # while building the runners: nothing written yet
        parser.exit(130, "python -m analysis.trace: interrupted before recording began\n")


if __name__ == "__main__":
    main()
