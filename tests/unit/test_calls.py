"""``sim.calls``: the cheap call into compiled code. ``Compiled`` must call exactly what the Numba
dispatcher would (the compiled function for the arguments' types, never a stale one when the
arguments change), and ``Deferred`` must hold Ctrl-C back inside and leave the program's own
handler alone."""

import os
import signal
from collections import namedtuple

import numpy as np
from numba import njit

import sim
from sim.calls import Compiled, Deferred

State = namedtuple("State", "values weights")


@njit
def _weighted(n, state, out):
    """out[0] = n * sum(values * weights); returns the type's size in bytes (to tell overloads
    apart)."""
    total = 0.0
    for i in range(state.values.shape[0]):
        total += state.values[i] * state.weights[i]
    out[0] = n * total
    return state.values.itemsize


def _state(dtype):
    return State(np.arange(4, dtype=dtype), np.ones(4, dtype=dtype))


def test_compiled_calls_the_overload_for_the_arguments_types():
    call = Compiled(_weighted)
    floats, ints = _state(np.float64), _state(np.int32)
    out = np.zeros(1)
    assert call(2, floats, out) == 8 and out[0] == 12.0  # compiled by the dispatcher
    assert call(3, floats, out) == 8 and out[0] == 18.0  # the cached entry, same objects
    # new objects of another type: typed again, never the float entry on int32 data
    assert call(1, ints, out) == 4 and out[0] == 6.0
    assert call(1, ints, out) == 4 and out[0] == 6.0
    # and back
    assert call(1, _state(np.float64), out) == 8 and out[0] == 6.0
    assert len(_weighted.signatures) == 2


def test_compiled_falls_back_to_the_dispatcher_for_other_shapes_of_call():
    """A step count that is not an int, or an output that is not a 1-D float64 array, is not
    typed by value: the dispatcher decides (and here compiles a third overload)."""
    call = Compiled(_weighted)
    out = np.zeros(1)
    assert call(2.5, _state(np.float64), out) == 8 and out[0] == 15.0
    assert call._entry is None


def test_compiled_keeps_its_entry_for_replaced_arrays_of_the_same_types(monkeypatch):
    """A World that grows a buffer passes a new named tuple of new arrays of the same types: the
    entry stands (typing the whole state again cost ~0.5 ms), and it computes on the new arrays."""
    call = Compiled(_weighted)
    out = np.zeros(1)
    assert call(1, _state(np.float64), out) == 8 and out[0] == 6.0
    lookups = []
    original = Compiled._lookup
    monkeypatch.setattr(
        Compiled, "_lookup", lambda self, args: lookups.append(1) or original(self, args)
    )
    grown = State(np.arange(8, dtype=np.float64), np.full(8, 2.0))
    assert call(1, grown, out) == 8 and out[0] == 56.0
    assert lookups == []
    # a strided view has another layout ("A", not "C"): typed again, never the contiguous entry
    strided = State(np.arange(8, dtype=np.float64)[::2], np.ones(8)[::2])
    assert call(1, strided, out) == 8 and out[0] == 12.0
    assert lookups == [1]
    # so has a read-only array
    frozen = State(np.arange(4, dtype=np.float64), np.ones(4))
    frozen.values.flags.writeable = False
    assert call(1, frozen, out) == 8 and out[0] == 6.0
    assert lookups == [1, 1]


def test_a_world_growing_its_buffers_types_its_state_once(monkeypatch):
    world = sim.World(sim.scenes.drop(200, seed=0))
    world.step(1)  # the state typed (and the kernel loaded) once
    lookups = []
    original = Compiled._lookup
    monkeypatch.setattr(
        Compiled, "_lookup", lambda self, args: lookups.append(1) or original(self, args)
    )
    world.step(99)
    assert world.inspect().regrown >= 3  # the contact store and the solver grew as the pile formed
    assert lookups == []


def test_a_world_stepped_one_call_at_a_time_is_the_same_run():
    scene = sim.scenes.drop(6, seed=2)
    whole = sim.World(scene, freeze="extended").step(90)
    single = sim.World(scene, freeze="extended")
    for _ in range(90):
        single.step(1)
    np.testing.assert_array_equal(whole.positions, single.positions)
    np.testing.assert_array_equal(whole.velocities, single.velocities)
    assert whole.events == single.events


def test_deferred_records_ctrl_c_instead_of_raising_it():
    before = signal.getsignal(signal.SIGINT)
    assert before is signal.default_int_handler  # pytest leaves Python's own handler
    with Deferred() as d:
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):  # the handler runs at the next bytecode boundaries
            pass
        assert d.came
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_deferred_leaves_the_programs_own_handler_alone():
    seen = []
    own = lambda signum, frame: seen.append(signum)  # noqa: E731
    previous = signal.signal(signal.SIGINT, own)
    try:
        with Deferred() as d:
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):
                pass
        assert seen == [signal.SIGINT] and not d.came
        assert signal.getsignal(signal.SIGINT) is own
    finally:
        signal.signal(signal.SIGINT, previous)


def test_compiled_shares_its_entries_and_never_serves_another_types_entry(monkeypatch):
    """A second ``Compiled`` (a new World) finds the entry the first one typed, without
    ``numba.typeof``; arguments whose types differ in any part (dtype, layout, a read-only
    array, an int beyond int64) are typed, never served the shared entry."""
    out = np.zeros(1)
    _weighted(1, _state(np.float64), out)  # compiled (a call that compiles shares nothing)
    assert Compiled(_weighted)(1, _state(np.float64), out) == 8  # typed and shared
    typed = []
    original = sim.calls.numba.typeof
    monkeypatch.setattr(sim.calls.numba, "typeof", lambda a: typed.append(1) or original(a))
    fresh = Compiled(_weighted)
    assert fresh(2, _state(np.float64), out) == 8 and out[0] == 12.0
    assert typed == []  # served from the shared entries
    # another dtype: its own entry (itemsize 4), never the float64 one
    assert Compiled(_weighted)(1, _state(np.int32), out) == 4 and out[0] == 6.0
    assert sim.calls._type_key(_state(np.int32)) != sim.calls._type_key(_state(np.float64))
    strided = State(np.arange(8, dtype=np.float64)[::2], np.ones(8)[::2])
    assert Compiled(_weighted)(1, strided, out) == 8 and out[0] == 12.0
    assert sim.calls._type_key(strided) != sim.calls._type_key(_state(np.float64))
    frozen = _state(np.float64)
    frozen.values.flags.writeable = False
    assert sim.calls._type_key(frozen) != sim.calls._type_key(_state(np.float64))
    assert sim.calls._type_key(2**63) is None and sim.calls._type_key(2**63 - 1) is int
    assert sim.calls._type_key((1, "a")) is None  # a member it cannot tell: not shared


def test_a_second_world_does_not_type_its_state_again(monkeypatch):
    scene = sim.scenes.drop(20, seed=1)
    sim.World(scene).step(2)  # typed (or compiled) once
    typed = []
    original = sim.calls.numba.typeof
    monkeypatch.setattr(sim.calls.numba, "typeof", lambda a: typed.append(1) or original(a))
    again = sim.World(scene).step(2)
    assert typed == []
    np.testing.assert_array_equal(again.positions, sim.World(scene).step(2).positions)
