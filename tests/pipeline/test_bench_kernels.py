"""experiments.bench_kernels: the instruction counter on known assembly (so a broken counter
fails), and the benchmark in quick mode, which must find packed double-precision arithmetic in
every batch kernel on this machine. No speed is asserted (speed lives in the results)."""

import json
import math

import pandas as pd
import pytest

from experiments import bench_kernels

SCALAR_ONLY = """
\t.text
\t.globl\tf
f:                                      # @f
# %bb.0:
\tvmovsd\t(%rdi), %xmm0                  # xmm0 = mem[0],zero
\tvmulsd\t8(%rdi), %xmm0, %xmm0
\tvaddsd\t%xmm1, %xmm0, %xmm0
\tvfmadd231sd\t%xmm2, %xmm3, %xmm0     # xmm0 = (xmm3 * xmm2) + xmm0
\tvmaxsd\t%xmm4, %xmm0, %xmm0
\tvucomisd\t%xmm0, %xmm1
\tmulsd\t%xmm1, %xmm0
\t# vmulpd in a comment is not an instruction
\tretq
"""

PACKED = """
.LBB0_2:
\tvmovupd\t(%rax), %zmm0
\tvmulpd\t64(%rax), %zmm0, %zmm1
\tvfnmadd213pd\t%zmm2, %zmm3, %zmm1
\tvsubpd\t%ymm1, %ymm2, %ymm3
\tvmaxpd\t%xmm1, %xmm2, %xmm3
\taddpd\t%xmm1, %xmm0
\tvaddpd\t(%rdi){1to8}, %zmm1, %zmm1 {%k1}
\tvcmpltpd\t%zmm1, %zmm2, %k1
\tvblendmpd\t%zmm1, %zmm2, %zmm3 {%k1}
\tvdivsd\t%xmm1, %xmm2, %xmm3
"""


def test_counter_finds_no_packed_instruction_in_scalar_code():
    counts = bench_kernels.count_instructions(SCALAR_ONLY)
    assert counts["packed"] == 0
    assert counts["scalar"] == 5  # vmulsd, vaddsd, vfmadd231sd, vmaxsd, mulsd
    assert math.isnan(counts["doubles_per_packed"])


def test_counter_counts_packed_arithmetic_by_register_width():
    counts = bench_kernels.count_instructions(PACKED)
    # vmulpd, vfnmadd213pd, vaddpd (zmm); vsubpd (ymm); vmaxpd, addpd (xmm); not moves,
    # compares or blends; vdivsd is scalar
    assert (counts["packed_zmm"], counts["packed_ymm"], counts["packed_xmm"]) == (3, 1, 2)
    assert counts["packed"] == 6 and counts["scalar"] == 1
    assert counts["doubles_per_packed"] == pytest.approx((3 * 8 + 4 + 2 * 2) / 6)


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bench_kernels")
    bench_kernels.main(["--quick"], data_dir=folder)
    return pd.read_csv(folder / "bench_kernels.csv"), json.loads(
        (folder / "bench_kernels.json").read_text()
    )


def test_every_batch_kernel_uses_packed_instructions_on_this_machine(quick):
    table, meta = quick
    assert set(table["kernel"]) == {f"soft_step.{k}" for k in bench_kernels.KERNELS}
    assert (table["packed"] > 0).all(), table[["kernel", "packed", "scalar"]]
    assert (table["packed"] > table["scalar"]).all()
    assert (table["doubles_per_packed"] >= 2).all()
    features = meta["parameters"]["cpu_features"]
    if features["avx2"]:
        # at least 4 doubles per instruction. Whether an AVX-512 CPU gets 8 (zmm) is LLVM's tuning
        # for the CPU it detects: for most AVX-512 cores (Skylake-X, Ice Lake, Rocket Lake) it
        # prefers 256-bit vectors. This machine's earlier CPU got zmm; as "rocketlake" it gets ymm
        assert (table["packed_ymm"] + table["packed_zmm"] > 0).all(), features["llvm_cpu_name"]
    assert features["numba_slp_vectorize"]


def test_quick_run_times_every_kernel_and_records_its_provenance(quick):
    table, meta = quick
    p = meta["parameters"]
    assert (table["ms_per_step"] > 0).all()
    assert (table["ns_per_contact_sweep"] > 0).all() and (table["ns_per_lane_sweep"] > 0).all()
    assert (table["contacts"] == p["contacts"]).all() and p["contacts"] > 0
    assert set(table["stage"]) <= set(p["profile_ms_per_step"])
    sweeps = dict(zip(table["kernel"], table["sweeps_per_step"]))
    assert sweeps["soft_step.solve"] == p["substeps"] * p["iterations"]
    assert sweeps["soft_step.relax"] == p["substeps"] * p["relax_iterations"]
    assert sweeps["soft_step.warm_start"] == p["substeps"]
    # once per pose after each position integration (the start poses' are part of prepare)
    assert sweeps["soft_step.arms"] == p["substeps"]
    assert meta["script"] == "bench_kernels" and p["quick"] is True
    assert meta["scenes"][0]["name"] == "pyramid"
    for key in ("git", "packages", "cpu", "platform", "date_utc"):
        assert meta[key]
