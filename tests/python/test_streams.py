"""Subscriptions of the Python client against the real tumbled: the three
encodings decode to the same arrays, DELTA keeps its baseline through
spawns and removals and asks for a key frame when it has none, events and
names."""

from __future__ import annotations

import numpy as np
import pytest

import tumble
from conftest import frames_until
from tumble.v1 import protocol_pb2 as pb

# The quantization's bounds (docs/protocol.md, "Pose encodings"), with a
# hair for the float32 of FULL frames.
POSITION_ERROR = 0.49e-3 + 1e-5
QUAT_ERROR = 2.4e-3
LINEAR_ERROR = 1 / 256 + 1e-5
ANGULAR_ERROR = 1 / 512 + 1e-5


def moving_world(count: int) -> dict:
    """`count` boxes on a grid, each moving and spinning its own way, no gravity."""
    rng = np.random.default_rng(7)
    bodies = []
    for i in range(count):
        bodies.append({"name": f"box{i}", "shape": {"box": {"half_extents": [0.1, 0.1, 0.1]}}, "mass": 1,
                       "position": [float(i % 32) * 0.5, float(i // 32) * 0.5, 0.0],
                       "linear_velocity": rng.uniform(-3, 3, 3).round(3).tolist(),
                       "angular_velocity": rng.uniform(-4, 4, 3).round(3).tolist()})
    return {"gravity": [0, 0, 0], "bodies": bodies}


def frames_of(subscription, count):
    out = []
    while len(out) < count:
        item = subscription.next(timeout=30)
        if isinstance(item, tumble.Frame):
            out.append(item)
    return out


def assert_same_state(full, other):
    assert full.tick == other.tick
    np.testing.assert_array_equal(full.ids, other.ids)
    np.testing.assert_allclose(other.positions, full.positions, rtol=0, atol=POSITION_ERROR)
    # q and -q are one rotation: compare up to sign.
    sign = np.sign(np.einsum("ij,ij->i", full.orientations, other.orientations))[:, None]
    np.testing.assert_allclose(other.orientations * sign, full.orientations, rtol=0, atol=QUAT_ERROR)
    np.testing.assert_allclose(other.linear_velocities, full.linear_velocities, rtol=0, atol=LINEAR_ERROR)
    np.testing.assert_allclose(other.angular_velocities, full.angular_velocities, rtol=0, atol=ANGULAR_ERROR)


def test_the_three_encodings_decode_to_the_same_arrays(make_server):
    server = make_server(moving_world(1000))
    with tumble.connect(server.address) as client:
        client.pause()
        streams = [client.subscribe(rate=0, encoding=e) for e in ("full", "quantized", "delta")]
        for _ in range(5):
            last = client.step(3, bodies=[0]).tick
        full, quantized, delta = [frames_until(s, last) for s in streams]
    common = sorted(set(full) & set(quantized) & set(delta))
    assert common[-1] == last
    for tick in common:
        assert len(full[tick]) == 1000
        assert full[tick].ids.dtype == np.uint32 and full[tick].positions.shape == (1000, 3)
        assert full[tick].orientations.shape == (1000, 4) and full[tick].positions.dtype == np.float64
        assert_same_state(full[tick], quantized[tick])
        assert_same_state(full[tick], delta[tick])
        np.testing.assert_array_equal(quantized[tick].positions, delta[tick].positions)
    # The world moved, so the comparison compared something.
    assert not np.allclose(full[min(full)].positions, full[last].positions, atol=0.01)


def test_delta_follows_spawns_and_removals(server):
    with tumble.connect(server.address) as client:
        client.pause()
        full = client.subscribe(rate=0, fields="pose")
        delta = client.subscribe(rate=0, encoding="delta", fields="pose")
        client.spawn("rock", sphere=0.2, at=(0, 4, 0), linear_velocity=(0, 1, 0))
        client.remove("ball")
        last = client.step(2).tick
        last_full = frames_until(full, last)[last]
        last_delta = frames_until(delta, last)[last]
    assert last_delta.names == ["crate", "pill", "rock"]
    assert last_delta.linear_velocities is None
    np.testing.assert_array_equal(last_full.ids, last_delta.ids)
    np.testing.assert_allclose(last_delta.positions, last_full.positions, atol=POSITION_ERROR)
    assert last_delta["rock"].position[1] == pytest.approx(4 + 2 / 240, abs=POSITION_ERROR)


def test_delta_without_its_baseline_asks_for_a_key_frame(server):
    with tumble.connect(server.address) as client:
        client.pause()
        stream = client.subscribe(rate=0, encoding="delta")
        first = frames_of(stream, 1)[0]
        assert len(first) == 3
        # The baseline is lost (as after a frame that would not decode): the
        # changes that follow (the pill spins, so every frame has one) cannot
        # be applied, and the client asks for a key frame.
        state = client._core.subscriptions[stream.id]
        state.baseline.arrays = None
        client.resume()
        after_key, following = frames_of(stream, 2)
        assert after_key.tick > first.tick
        assert len(after_key) == 3 and len(following) == 3, "every body, not a change applied to nothing"
        assert not state.key_frame_asked, "the key frame came"


def test_events_come_with_their_frames_and_names(server):
    with tumble.connect(server.address) as client:
        client.pause()
        stream = client.subscribe(bodies=None, rate=0, events=["spawned", "removed"])
        rock = client.spawn("rock", sphere=0.2)
        client.remove(rock)
        items = []
        while len([i for i in items if isinstance(i, tumble.Event)]) < 2:
            items.append(stream.next(timeout=30))
        events = [i for i in items if isinstance(i, tumble.Event)]
        assert [(e.kind, e.body_id, e.body_name) for e in events] == [("spawned", rock, "rock"),
                                                                      ("removed", rock, "rock")]


def test_a_stream_learns_the_names_of_bodies_another_client_spawned(server):
    with tumble.connect(server.address) as watcher, tumble.connect(server.address) as other:
        other.pause()
        stream = watcher.subscribe(rate=0, encoding="quantized")
        frames_of(stream, 1)
        other.spawn("stranger", box=(0.2, 0.2, 0.2), at=(9, 0, 0))
        frame = frames_of(stream, 1)[0]  # the edit's frame, at once while paused
        assert frame.names == ["crate", "ball", "pill", "stranger"]
        np.testing.assert_allclose(frame["stranger"].position, [9, 0, 0], atol=POSITION_ERROR)


def test_unsubscribe_ends_the_stream(server):
    with tumble.connect(server.address) as client:
        stream = client.subscribe(rate=60)
        frames_of(stream, 2)
        stream.close()
        with pytest.raises(StopIteration):
            next(stream)
        assert client.stats()["clients"] == 1
