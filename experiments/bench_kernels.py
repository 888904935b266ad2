"""Table "bench_kernels": does the contact solver's compiled code use packed vector instructions,
and what does one contact cost per sweep?

Question (issue "Solver v2": "show in a bench script that the compiled kernel uses packed vector
instructions"): sim's soft-step solver lays its contacts out in batches of ``soft_step.LANES``
(8) lanes, field by field, so that LLVM's SLP vectoriser can turn the lane loops into packed
instructions (``sim/jit.py`` says which conditions that needs). Whether it did is a property of
the machine code, not of the source: this reads it.

1. Instructions. For each batch kernel of ``sim.soft_step`` (``arms``, ``warm_start``, ``solve``,
   ``relax``)
   the x86 assembly of its compiled specialisation, for the argument types a World passes, is
   read with ``Dispatcher.inspect_asm`` and its double-precision arithmetic instructions are
   counted (``count_instructions``): packed (add, sub, mul, div, max, min, sqrt and every fused
   multiply-add form ending in ``pd``), by register width (xmm 2 doubles, ymm 4, zmm 8), against
   scalar (the same ending in ``sd``). Moves, compares and blends are not arithmetic and are not
   counted. Numba does not keep the assembly of code it loaded from its on-disk cache (the World's
   kernels usually are), and a kernel called only from other compiled code has no signature of
   its own; so, unless the dispatcher itself holds freshly compiled code for those types, the
   assembly is that of an uncached twin: the same Python function compiled by ``numba.njit`` with
   the dispatcher's own options (fast-math ``contract``, error model, no reference counting) and
   the global SLP switch ``sim.jit`` sets, for the same argument types (checked against the
   types in the step loop's signature). Same source, options, types and LLVM: the same code.
   ``asm_source`` says which was read.
2. Cost. pyramid(base) under ``off`` (every contact solved every step), after WARMUP_STEPS
   steps: R repeats of ``World.profile(K)``, median ms per step of each kernel's stage, divided by
   the work it did: ``ns_per_contact_sweep`` = stage time / (active contacts x sweeps per step),
   where a sweep visits every contact once (solve: substeps x iterations; relax: substeps x
   relax_iterations; warm_start: substeps; arms, which computes every point's lever arms
   and separation once per pose after each position integration: substeps; those of the start
   poses are part of ``prepare``). ``ns_per_lane_sweep`` divides by the
   lanes swept instead (batches x LANES: part-filled batches are paid in full). A contact is one
   pair's manifold (up to 2 points; a box on a box has 2), with its friction rows (the pyramid's
   friction is 0.6).

Scenes: pyramid(100) (5050 boxes, ~10^4 contacts; quick: pyramid(10)); sim.World defaults (dt
1/60 s, 4 substeps, 1 iteration, 1 relax iteration).

    python -m experiments.bench_kernels [--quick]
writes results/data/bench_kernels.csv + .json (with the CPU's name and vector features).
"""

import inspect
import re
import statistics
import warnings

import numba
import numpy as np
import pandas as pd

import sim
from study.common import DT, entry
from sim import kernel as step_loop
from sim import soft_step
from sim.data import Solver

NAME = "bench_kernels"
WARMUP_STEPS = 10
FULL = {"pyramid": 100, "steps": 20, "repeats": 7}
QUICK = {"pyramid": 10, "steps": 5, "repeats": 3}

#: the batch kernels, the profile stage each one's time is in, and how many sweeps over the
#: contacts it makes per step (from the World)
KERNELS = {
    "arms": ("arms", lambda w: w.substeps),
    "warm_start": ("warm_start", lambda w: w.substeps),
    "solve": ("solve", lambda w: w.substeps * w.iterations),
    "relax": ("relax", lambda w: w.substeps * w.relax_iterations),
}
#: example values of the kernels' scalar parameters, by name: zero counts, so a call compiles
#: the kernel for these types and does nothing
SCALAR_EXAMPLES = {
    "n_colours": 0,
    "n_batches": 0,
    "inv_h": 1.0 / (DT / 4),
    "push": 3.0,
    "skip_frictionless": True,
}

_ARITH = r"(?:add|sub|mul|div|max|min|sqrt|f(?:n?m(?:add|sub)|maddsub|msubadd)(?:132|213|231))"
#: a double-precision arithmetic instruction, packed (pd) or scalar (sd), VEX/EVEX or SSE form
_INSTRUCTION = re.compile(rf"^\s*(v?){_ARITH}(pd|sd)\b(.*)$")
_WIDTH = {"zmm": 8, "ymm": 4, "xmm": 2}


def count_instructions(asm):
    """Double-precision arithmetic instructions in x86 assembly text (AT&T or Intel syntax):
    {"packed_xmm", "packed_ymm", "packed_zmm": packed ones by their widest register,
    "packed": their sum, "scalar": scalar ones, "doubles_per_packed": mean doubles per packed
    instruction (nan without any)}. Labels, directives and comments are skipped."""
    out = {"packed_xmm": 0, "packed_ymm": 0, "packed_zmm": 0, "scalar": 0}
    for line in asm.splitlines():
        line = line.split("#", 1)[0]
        m = _INSTRUCTION.match(line)
        if m is None:
            continue
        kind, operands = m.group(2), m.group(3)
        if kind == "sd":
            out["scalar"] += 1
            continue
        regs = re.findall(r"\b(zmm|ymm|xmm)\d+", operands)
        widest = max(regs, key=_WIDTH.get) if regs else "xmm"  # SSE without a register: 128 bit
        out[f"packed_{widest}"] += 1
    packed = out["packed_xmm"] + out["packed_ymm"] + out["packed_zmm"]
    doubles = sum(out[f"packed_{r}"] * w for r, w in _WIDTH.items())
    out["packed"] = packed
    out["doubles_per_packed"] = doubles / packed if packed else float("nan")
    return out


def world_solver_types():
    """{Solver field: numba type} as the compiled step loop receives them (from the signature a
    World's run registered on ``sim.kernel.run``)."""
    if not step_loop.run.signatures:
        raise RuntimeError("no World has run in this process: sim.kernel.run has no signature")
    names = list(inspect.signature(step_loop.run.py_func).parameters)
    solver_type = step_loop.run.signatures[0][names.index("solver")]
    return dict(zip(Solver._fields, solver_type.types))


def example_arguments(dispatcher, solver_types):
    """Arguments of the World's types for ``dispatcher`` (a batch kernel): its array parameters
    are Solver fields (one-element arrays of the field's dtype and rank), its scalars zero counts
    and plain floats (``SCALAR_EXAMPLES``)."""
    args = []
    for name in inspect.signature(dispatcher.py_func).parameters:
        if name in solver_types:
            t = solver_types[name]
            args.append(np.zeros((1,) * t.ndim, dtype=np.dtype(str(t.dtype))))
        elif name in SCALAR_EXAMPLES:
            args.append(SCALAR_EXAMPLES[name])
        else:
            raise KeyError(
                f"{dispatcher.__name__}: no example for parameter {name!r}; "
                f"add it to SCALAR_EXAMPLES"
            )
    return args


def kernel_asm(dispatcher, solver_types):
    """(assembly text, signature, source) of ``dispatcher``'s code for the World's types (see the
    module docstring: the dispatcher's own when inspectable, else an uncached twin's)."""
    args = example_arguments(dispatcher, solver_types)
    signature = tuple(numba.typeof(a) for a in args)
    for name, t in zip(inspect.signature(dispatcher.py_func).parameters, signature):
        if name in solver_types and t != solver_types[name]:
            raise RuntimeError(
                f"{dispatcher.__name__}.{name}: example type {t} is not the "
                f"World's {solver_types[name]}"
            )
    if signature in dispatcher.signatures:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # "Inspection disabled for cached code"
            asm = dispatcher.inspect_asm(signature)
        if count_instructions(asm)["packed"] + count_instructions(asm)["scalar"] > 0:
            return asm, signature, "dispatcher"
    options = {k: v for k, v in dispatcher.targetoptions.items() if k not in ("cache", "nopython")}
    twin = numba.njit(**options)(dispatcher.py_func)
    twin(*args)  # compiles; zero counts do nothing
    return twin.inspect_asm(signature), signature, "uncached twin (same function and options)"


def cpu_features():
    """The host CPU as LLVM sees it (what Numba compiles for) and its vector extensions."""
    import llvmlite.binding as llvm

    features = llvm.get_host_cpu_features()
    return {
        "llvm_cpu_name": llvm.get_host_cpu_name(),
        **{
            f: bool(features.get(f, False))
            for f in ("sse2", "avx", "avx2", "fma", "avx512f", "avx512vl")
        },
        "numba_slp_vectorize": bool(numba.config.SLP_VECTORIZE),
    }


def cost(config):
    """(world, median ms per step of every profile stage) on pyramid(base), nothing frozen."""
    world = sim.World(sim.scenes.pyramid(config["pyramid"]), dt=DT)
    world.step(WARMUP_STEPS)
    profiles = [world.profile(config["steps"]) for _ in range(config["repeats"])]
    return world, {stage: statistics.median(p[stage] for p in profiles) for stage in profiles[0]}


def run(config, args):
    sim.World(sim.scenes.stack(2), dt=DT).profile(2)  # compile (or load) the step loop
    world, stage_ms = cost(config)
    look = world.inspect()
    solver_types = world_solver_types()
    lanes = look.n_batches * look.lanes
    rows = []
    for name, (stage, sweeps_of) in KERNELS.items():
        asm, signature, source = kernel_asm(getattr(soft_step, name), solver_types)
        counts = count_instructions(asm)
        sweeps = sweeps_of(world)
        ms = stage_ms[stage]
        rows.append(
            {
                "kernel": f"soft_step.{name}",
                "signature": str(signature),
                "asm_source": source,
                **counts,
                "packed_share": (
                    counts["packed"] / (counts["packed"] + counts["scalar"])
                    if counts["packed"] + counts["scalar"]
                    else float("nan")
                ),
                "stage": stage,
                "ms_per_step": ms,
                "sweeps_per_step": sweeps,
                "contacts": look.n_active,
                "lanes": lanes,
                "ns_per_contact_sweep": (
                    1e6 * ms / (look.n_active * sweeps)
                    if sweeps and look.n_active
                    else float("nan")
                ),
                "ns_per_lane_sweep": (
                    1e6 * ms / (lanes * sweeps) if sweeps and lanes else float("nan")
                ),
            }
        )
    table = pd.DataFrame(rows)
    scene = world.scene
    parameters = {
        "dt": DT,
        "warmup_steps": WARMUP_STEPS,
        "repeats": config["repeats"],
        "steps_per_repeat": config["steps"],
        "substeps": world.substeps,
        "iterations": world.iterations,
        "relax_iterations": world.relax_iterations,
        "freeze": world.freeze,
        "lanes_per_batch": look.lanes,
        "contacts": look.n_active,
        "colours": look.n_colours,
        "batches": look.n_batches,
        "batch_fill": look.batch_fill,
        "profile_ms_per_step": stage_ms,
        "cpu_features": cpu_features(),
    }
    return table, [scene], parameters


main = entry(NAME, __doc__, FULL, QUICK, run)

if __name__ == "__main__":
    main()
