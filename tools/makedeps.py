"""The Makefile's dependencies, read from the code: which source files each output is made from.

    python3 tools/makedeps.py --out FILE NAME [NAME ...]    make rules into FILE (atomically)

A results file depends on every repository module its script imports, directly or through other
modules (``fig_speedup`` imports ``protocols``, which imports ``common``, which imports
``sim``...). Listed by hand, these went stale: after an edit to ``bench_freeze.py`` (then also the
figures' library), ``make reproduce`` did not rerun ``fig_speedup``, ``fig_scaling`` nor
``fig_time_to_rest``. Here they are found by parsing the imports (``ast``: nothing is imported or
run, so this needs no virtualenv and takes a fraction of a second), so the build graph is right by
construction.

Printed rules only add prerequisites; the recipes stay in the Makefile:
    $(DATA)/<name>.csv    experiments/<name>.py and all it imports
    $(GEN)/<name>.json    analysis/<name>.py and all it imports (and the .csv, in the Makefile)
    TRACE_DEPS, PAPER_DEPS, GLANCE_DEPS   what analysis.trace / .paper / .glance import
"""

import ast
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: the repository's own top-level packages (imports of anything else are third-party)
PACKAGES = ("sim", "study", "experiments", "analysis")


def module_file(module):
    """The file of a dotted module name in the repository, or None (third-party, or a name
    inside a module rather than a module)."""
    parts = module.split(".")
    if parts[0] not in PACKAGES:
        return None
    base = ROOT.joinpath(*parts)
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _parents(module):
    """Importing a.b.c runs a/__init__.py and a/b/__init__.py first."""
    parts = module.split(".")
    return [".".join(parts[:k]) for k in range(1, len(parts))]


def imported_modules(path, module):
    """Dotted names of the repository modules ``path`` (module ``module``) imports anywhere in
    its body (imports inside functions count: they run when the script runs)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: from . import x, from .a import b
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([node.module] if node.module else []))
            else:
                base = node.module
            # `from pkg import name`: name may be a submodule or an attribute of pkg
            names = [base] + [f"{base}.{alias.name}" for alias in node.names]
        else:
            continue
        for name in names:
            for candidate in _parents(name) + [name]:
                if module_file(candidate) is not None:
                    found.add(candidate)
    return found


def dependencies(module):
    """Every repository file ``module`` runs when imported or run: itself and all it imports,
    transitively, sorted."""
    seen, todo = set(), [module, *_parents(module)]
    while todo:
        name = todo.pop()
        if name in seen or module_file(name) is None:
            continue
        seen.add(name)
        todo.extend(imported_modules(module_file(name), name) - seen)
    return sorted(str(module_file(name).relative_to(ROOT)) for name in seen)


def rules(names):
    out = []
    for name in names:
        out.append(f"$(DATA)/{name}.csv: {' '.join(dependencies(f'experiments.{name}'))}")
        out.append(f"$(GEN)/{name}.json: {' '.join(dependencies(f'analysis.{name}'))}")
    for var, module in (
        ("TRACE_DEPS", "analysis.trace"),
        ("PAPER_DEPS", "analysis.paper"),
        ("GLANCE_DEPS", "analysis.glance"),
    ):
        out.append(f"{var} := {' '.join(dependencies(module))}")
    return "\n".join(out) + "\n"


def write(path, text):
    """``text`` into ``path`` whole or not at all: a temporary file beside it, flushed to disk,
    renamed over it; a failed write (a full disk) raises, so the caller's make stops. Written
    through the shell's redirection (until 2026-12-07), a full disk cut the rules off mid-path
    with exit status 0: the cut file was newer than every source, and every make command after it
    failed on "No rule to make target 'sim/fre'" until it was deleted by hand."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp")
    try:
        with open(tmp, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:  # (its folder is not one)
            pass
        sys.exit(f"tools/makedeps.py: cannot write {path}: {exc}")


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) < 2 or args[0] != "--out":
        sys.exit("usage: python3 tools/makedeps.py --out FILE NAME [NAME ...]")
    write(args[1], "# made by tools/makedeps.py from the imports; do not edit\n" + rules(args[2:]))
