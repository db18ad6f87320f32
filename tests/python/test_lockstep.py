"""Lockstep with the Python client against the real tumbled: Client.step
applies its forces for its ticks only and answers with the state after the
last tick in one round trip, and a paused server takes a Step up as it
arrives rather than at its loop's next tick."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

import tumble

DT = 1 / 240


def test_step_forces_act_for_its_ticks_only(server):
    with tumble.connect(server.address) as client:
        client.pause()
        frame = client.step(10, forces={"crate": (10, 0, 0)}, torques={"ball": (0, 0, 0.036)})
        a = 10 / 2
        assert frame["crate"].linear_velocity[0] == pytest.approx(10 * a * DT, rel=1e-5)
        assert frame["crate"].position[0] == pytest.approx(a * DT * DT * 10 * 11 / 2, rel=1e-5)
        # A solid sphere of 1 kg and 0.3 m: I = 0.036 kg m^2, so 1 rad/s^2.
        assert frame["ball"].angular_velocity[2] == pytest.approx(10 * DT, rel=1e-5)
        after = client.step(10)
        assert after["crate"].linear_velocity[0] == pytest.approx(10 * a * DT, rel=1e-5), \
            "the Step's force must not act after its ticks"
        assert after["ball"].angular_velocity[2] == pytest.approx(10 * DT, rel=1e-5)
        assert after.tick == frame.tick + 10


def test_a_step_frame_holds_the_bodies_and_fields_asked(server):
    with tumble.connect(server.address) as client:
        client.pause()
        frame = client.step(1, bodies=["pill", 0], fields="pose")
        assert frame.names == ["crate", "pill"]
        assert frame.linear_velocities is None and frame.angular_velocities is None
        with pytest.raises(tumble.ServerError) as unknown:
            client.step(1, forces={"nobody": (1, 0, 0)})
        assert unknown.value.code == "UNKNOWN_BODY"
        assert client.step(1).tick == frame.tick + 1, "the refused Step stepped nothing"


def test_a_step_cut_short_raises_with_the_tick_it_reached(server):
    with tumble.connect(server.address, timeout=60) as stepper, tumble.connect(server.address) as other:
        start = stepper.pause()
        outcome = {}

        def run():
            try:
                stepper.step(1_000_000, forces={"crate": (1, 0, 0)})
            except tumble.StepCutShort as cut:
                outcome["cut"] = cut

        thread = threading.Thread(target=run)
        thread.start()
        stream = other.subscribe(rate=0, bodies=["crate"])
        # Wait until the Step is under way: a frame past the tick it started at.
        while stream.next(timeout=30).tick <= start:
            pass
        other.pause()
        thread.join(60)
        cut = outcome["cut"]
        assert cut.ended_by == "pause"
        assert 0 < cut.ticks_left < 1_000_000
        assert cut.frame.tick == start + 1_000_000 - cut.ticks_left
        # The Step's force ended with it.
        v = cut.frame["crate"].linear_velocity[0]
        assert other.step(5)["crate"].linear_velocity[0] == pytest.approx(v, rel=1e-6)


def test_a_paused_server_takes_a_step_as_it_arrives(make_server):
    # At 1 Hz, a Step served at the loop's next tick would wait for it: 40 in a
    # row would take at least 39 s. Served as they arrive they take well under
    # a second, so the bound below is far from both, even on a loaded machine.
    server = make_server(args=["--tick-rate", "1"])
    with tumble.connect(server.address) as client:
        client.pause()
        started = time.monotonic()
        for _ in range(40):
            client.step(1)
        elapsed = time.monotonic() - started
    assert elapsed < 20.0, f"40 lockstep round trips took {elapsed:.2f} s at a 1 Hz tick rate"


def test_lockstep_over_the_async_client_matches_the_sync_one(server):
    import asyncio

    import tumble.aio

    async def run():
        async with await tumble.aio.connect(server.address) as client:
            await client.pause()
            return [await client.step(2, forces={"crate": (4, 0, 0)}) for _ in range(3)]

    frames = asyncio.run(run())
    # 6 ticks of 4 N on 2 kg.
    assert frames[-1]["crate"].linear_velocity[0] == pytest.approx(6 * 2 * DT, rel=1e-5)
    assert [f.tick for f in frames] == [frames[0].tick, frames[0].tick + 2, frames[0].tick + 4]
