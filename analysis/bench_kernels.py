"""Table "bench_kernels": packed against scalar double-precision arithmetic in the compiled batch
kernels of sim's contact solver, and what a contact costs per sweep.

Writes paper/generated/bench_kernels.csv (one row per kernel: packed instructions by register
width, scalar ones, ns per contact per sweep) and bench_kernels.json (the same per kernel, the
CPU and its vector features, the scene's contacts and batch fill)."""

from analysis import style

NAME = "bench_kernels"
WIDTH_BITS = {"packed_xmm": 128, "packed_ymm": 256, "packed_zmm": 512}


def draw(table, meta):
    shown = table.assign(kernel=table["kernel"].str.replace("soft_step.", "", regex=False))
    style.write_table(
        shown[
            [
                "kernel",
                "packed_zmm",
                "packed_ymm",
                "packed_xmm",
                "scalar",
                "ns_per_contact_sweep",
                "ns_per_lane_sweep",
                "sweeps_per_step",
            ]
        ].round({"ns_per_contact_sweep": 1, "ns_per_lane_sweep": 1}),
        NAME,
    )
    p = meta["parameters"]
    widest = {}
    for r in table.itertuples():
        used = [bits for col, bits in WIDTH_BITS.items() if getattr(r, col) > 0]
        widest[r.kernel] = max(used) if used else 0
    scene = meta["scenes"][0] if meta.get("scenes") else {}
    return {
        "kernels": {
            r.kernel: {
                "packed": int(r.packed),
                "scalar": int(r.scalar),
                "packed_xmm": int(r.packed_xmm),
                "packed_ymm": int(r.packed_ymm),
                "packed_zmm": int(r.packed_zmm),
                "doubles_per_packed": r.doubles_per_packed,
                "widest_bits": widest[r.kernel],
                "asm_source": r.asm_source,
                "ms_per_step": r.ms_per_step,
                "ns_per_contact_sweep": r.ns_per_contact_sweep,
                "ns_per_lane_sweep": r.ns_per_lane_sweep,
            }
            for r in table.itertuples()
        },
        "all_packed": bool((table["packed"] > 0).all() and (table["scalar"] == 0).all()),
        "packed_total": int(table["packed"].sum()),
        "scalar_total": int(table["scalar"].sum()),
        "cpu": meta.get("cpu"),
        "cpu_features": p.get("cpu_features", {}),
        "scene": {
            "name": scene.get("name"),
            "params": scene.get("params"),
            "bodies": scene.get("bodies"),
        },
        "contacts": p["contacts"],
        "batch_fill": p["batch_fill"],
        "lanes_per_batch": p["lanes_per_batch"],
        "substeps": p["substeps"],
        "iterations": p["iterations"],
        "relax_iterations": p["relax_iterations"],
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
