"""Joints in the Python client's frames against the real tumbled: a
subscription with joints=True carries every joint of the world in each
encoding and with any body filter, the same float32 values for the same
tick; without it the joint arrays are None; a lockstep Step with
joints=True answers with hinge angles whose change is their speed
integrated over the ticks; a frame whose joint arrays disagree is refused."""

from __future__ import annotations

import asyncio
import json
import os

import numpy as np
import pytest

import tumble
import tumble.aio
from conftest import SOURCE, frames_until
from tumble._core import Core
from tumble._poses import PackedError, decode_joints
from tumble.v1 import protocol_pb2 as pb

DT = 1 / 240  # s, tumbled's default tick
SCENES = os.environ.get("TUMBLE_SCENES", os.path.join(SOURCE, "..", "..", "scenes"))
ENCODINGS = ("full", "quantized", "delta")
HINGES = ("pivot", "upper-pivot", "lower-pivot")
# float32 on the wire: a hinge angle of at most a few rad is within 2.4e-7
# rad of the server's double; twice that over the two ends of a change, and
# the sum of k float32 speeds, stay well below this.
FLOAT32_SLACK = 1e-5  # rad


def scene(name: str) -> dict:
    """A scene file of scenes/, as a dict."""
    with open(os.path.join(SCENES, name)) as f:
        return json.load(f)


@pytest.fixture
def pendulums(make_server):
    """tumbled on scenes/pendulums.json: three hinges (a pendulum, a double pendulum) and ten distance joints."""
    return make_server(scene("pendulums.json"))


def listed_joints(client: tumble.Client) -> pb.JointList:
    """Every joint as ListJoints gives it (one page: the scene's few fit), with the tick it is of."""
    listing = client._call(("list_joints", pb.ListJoints(), lambda reply: reply.joint_list))
    assert listing.next_start_id == 0, "the scene's joints fit in one page"
    return listing


def joint_values(frame: tumble.Frame) -> np.ndarray:
    """A frame's joint positions, speeds and motor impulses, (3, J)."""
    return np.stack([frame.joint_positions, frame.joint_speeds, frame.joint_motor_impulses])


def test_every_encoding_carries_every_joint_with_the_same_values(pendulums):
    with tumble.connect(pendulums.address) as client:
        client.pause()
        streams = {encoding: client.subscribe(rate=0, encoding=encoding, joints=True) for encoding in ENCODINGS}
        # A body filter leaves the joints whole; a static body's DELTA frames
        # after the first change no body, and carry the joints all the same.
        streams["ground only"] = client.subscribe(bodies=["ground"], rate=0, encoding="delta", joints=True)
        for _ in range(4):
            last = client.step(6).tick
        frames = {name: frames_until(stream, last) for name, stream in streams.items()}
        listing = listed_joints(client)
    assert listing.tick == last
    listed_ids = np.array([j.id for j in listing.joints], dtype=np.uint32)
    assert listed_ids.shape == (len(scene("pendulums.json")["joints"]),) == (13,)
    common = sorted(set.intersection(*(set(by_tick) for by_tick in frames.values())))
    assert common[-1] == last and len(common) >= 2
    for tick in common:
        full = frames["full"][tick]
        for name, by_tick in frames.items():
            frame = by_tick[tick]
            assert frame.joint_ids.dtype == np.uint32 and frame.joint_positions.dtype == np.float64
            np.testing.assert_array_equal(frame.joint_ids, listed_ids, err_msg=name)
            values = joint_values(frame)
            assert values.shape == (3, 13)
            assert np.all(np.isfinite(values)), name
            np.testing.assert_array_equal(values, joint_values(full), err_msg=f"{name} at tick {tick}")
    # The frames of the last tick hold what ListJoints says of it, to float32.
    listed = np.array([[j.state.position for j in listing.joints], [j.state.speed for j in listing.joints],
                       [j.state.motor_impulse for j in listing.joints]], dtype=np.float32)
    np.testing.assert_array_equal(joint_values(frames["full"][last]), listed.astype(np.float64))
    # The hinges swung, so the comparisons compared something.
    hinges = [i for i, j in enumerate(listing.joints) if j.name in HINGES]
    first, final = frames["delta"][common[0]], frames["delta"][last]
    assert np.all(np.abs(final.joint_positions[hinges] - first.joint_positions[hinges]) > 1e-3)
    assert np.all(np.abs(final.joint_speeds[hinges]) > 1e-2)


def test_frames_hold_joints_only_when_asked(pendulums, server):
    with tumble.connect(pendulums.address) as client:
        client.pause()
        plain = [client.subscribe(rate=0, encoding=encoding) for encoding in ENCODINGS]
        last = client.step(2).tick
        frames = [frames_until(stream, last)[last] for stream in plain] + [client.step(1)]
    for frame in frames:
        assert frame.joint_ids is None and frame.joint_positions is None
        assert frame.joint_speeds is None and frame.joint_motor_impulses is None
        assert len(frame) == 9, "the bodies are there"
    # Asked of a world without joints: empty arrays, not None.
    with tumble.connect(server.address) as client:
        client.pause()
        frames = [frames_until(client.subscribe(rate=0, encoding=encoding, joints=True), client.step(1).tick)
                  for encoding in ENCODINGS]
        stepped = client.step(1, joints=True)
    for frame in [f[max(f)] for f in frames] + [stepped]:
        assert frame.joint_ids is not None and frame.joint_ids.shape == (0,)
        assert frame.joint_positions.shape == frame.joint_speeds.shape == frame.joint_motor_impulses.shape == (0,)


def test_lockstep_hinge_angles_are_their_speeds_integrated(pendulums):
    ticks = 120
    with tumble.connect(pendulums.address) as client:
        client.pause()
        names = {j.id: j.name for j in listed_joints(client).joints}
        frames = [client.step(1, bodies=["bob"], joints=True) for _ in range(ticks + 1)]
    assert [f.tick for f in frames] == list(range(frames[0].tick, frames[0].tick + ticks + 1))
    assert [names[int(i)] for i in frames[0].joint_ids[:3]] == list(HINGES)
    angles = np.array([f.joint_positions[:3] for f in frames])  # (ticks + 1, 3), rad
    speeds = np.array([f.joint_speeds[:3] for f in frames])  # rad/s
    assert np.all(np.diff(angles, axis=0) != 0), "each hinge turns on every tick"
    # A tick's change of angle is dt times a speed between the speeds at its
    # two ends (the speed changes one way over a tick of a pendulum): within
    # dt |w1 - w0| / 2 of dt (w0 + w1) / 2. The joints are soft, so their
    # push against drift moves an angle by a little more, under 1 % of the
    # change as measured; 2 % of it is allowed. A speed that is off by more,
    # missing or of the wrong sign fails.
    for k in (1, 24, ticks):
        for start in range(0, ticks - k + 1, k):
            window = slice(start, start + k + 1)
            change = angles[start + k] - angles[start]
            tick_means = (speeds[window][1:] + speeds[window][:-1]) / 2
            integrated = DT * tick_means.sum(axis=0)
            moved = np.abs(np.diff(angles[window], axis=0)).sum(axis=0)
            bound = DT / 2 * np.abs(np.diff(speeds[window], axis=0)).sum(axis=0) + 0.02 * moved + FLOAT32_SLACK
            assert np.all(np.abs(change - integrated) <= bound), \
                f"ticks {start} to {start + k}: angle change {change}, speeds integrated {integrated}, bound {bound}"
    # The pendulum fell from level: a quarter turn takes about 0.6 s, so in
    # 0.5 s it turned by more than a few tenths of a radian, one way.
    assert abs(angles[-1, 0] - angles[0, 0]) > 0.3
    assert np.all(np.sign(speeds[1:, 0]) == np.sign(angles[-1, 0] - angles[0, 0]))


def test_the_async_client_asks_for_joints_too(pendulums):
    async def run():
        async with await tumble.aio.connect(pendulums.address) as client:
            await client.pause()
            stream = await client.subscribe(rate=0, encoding="delta", joints=True)
            stepped = await client.step(3, joints=True)
            while True:
                item = await stream.next(timeout=30)
                if isinstance(item, tumble.Frame) and item.tick == stepped.tick:
                    return stepped, item

    stepped, streamed = asyncio.run(run())
    assert stepped.joint_ids.shape == (13,)
    np.testing.assert_array_equal(stepped.joint_ids, streamed.joint_ids)
    np.testing.assert_array_equal(joint_values(stepped), joint_values(streamed))


def test_a_frame_whose_joint_arrays_disagree_is_refused():
    broken = pb.PoseFrame(subscription_id=5, tick=8, joint_ids=[1, 2], joint_positions=[0.5, 0.25],
                          joint_speeds=[1.0], joint_motor_impulses=[0.0, 0.0])
    with pytest.raises(PackedError):
        decode_joints(broken)
    # In a subscription's stream it is dropped; the next frame is taken.
    core = Core()
    kind, message = Core.subscribe(None, 0, "full", "pose", False, True)
    request_id, _ = core.frame(kind, message)
    replies = [pb.ServerMessage(subscribed=pb.Subscribed(request_id=request_id, subscription_id=5, rate_hz=240)),
               pb.ServerMessage(pose_frame=broken)]
    whole = pb.PoseFrame(subscription_id=5, tick=9, joint_ids=[2, 1], joint_positions=[0.25, 0.5],
                         joint_speeds=[2.0, 1.0], joint_motor_impulses=[0.0, 0.125])
    replies.append(pb.ServerMessage(pose_frame=whole))
    for reply in replies:
        data = reply.SerializeToString()
        core.feed(bytes([len(data)]) + data)
    frames = list(core.subscriptions[5].items)
    assert [f.tick for f in frames] == [9]
    np.testing.assert_array_equal(frames[0].joint_ids, [1, 2])
    np.testing.assert_array_equal(joint_values(frames[0]), [[0.5, 0.25], [1.0, 2.0], [0.125, 0.0]])
