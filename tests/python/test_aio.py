"""tumble.aio against the real tumbled: the same requests with async/await,
subscriptions read with async for, tasks sharing one client, and errors."""

from __future__ import annotations

import asyncio

import numpy as np
import pytest

import tumble
import tumble.aio


def run(coroutine):
    return asyncio.run(coroutine)


def test_requests_and_a_stream(server):
    async def main():
        async with await tumble.aio.connect(server.address) as client:
            bodies = await client.bodies()
            assert [b.name for b in bodies] == ["crate", "ball", "pill"]
            await client.pause()
            rock = await client.spawn("rock", sphere=0.1, at=(0, 2, 0))
            stream = await client.subscribe(bodies=["rock"], rate=0, encoding="delta")
            await client.set("rock", linear_velocity=(0, -1, 0))
            last = (await client.step(24)).tick
            seen = []
            async for item in stream:
                seen.append(item)
                if item.tick >= last:
                    break
            await stream.close()
            stats = await client.stats()
            return rock, seen, stats

    rock, frames, stats = run(main())
    assert frames[-1].names == ["rock"]
    assert frames[-1][rock].position[1] == pytest.approx(2 - 24 / 240, abs=0.5e-3)
    assert stats["paused"] and stats["bodies"] == 4


def test_tasks_share_one_client(server):
    async def main():
        async with await tumble.aio.connect(server.address) as client:
            paused_at = await client.pause()
            stream = await client.subscribe(bodies=["crate"], rate=0)

            async def read_frames():
                # Up to the frame of the last Step's tick. Any frame before it
                # may be replaced by a newer one before it is sent (latest wins),
                # the first one included.
                frames = [await stream.next(timeout=30)]
                while frames[-1].tick < paused_at + 4:
                    frames.append(await stream.next(timeout=30))
                return paused_at, frames

            async def step():
                return [(await client.step(1)).tick for _ in range(4)]

            return await asyncio.gather(read_frames(), step(), client.bodies())

    (paused_at, frames), ticks, bodies = run(main())
    assert ticks == [paused_at + 1, paused_at + 2, paused_at + 3, paused_at + 4]
    assert frames[-1].tick == ticks[-1]
    assert [f.tick for f in frames] == sorted({f.tick for f in frames})
    assert paused_at <= frames[0].tick
    assert len(bodies) == 3


def test_errors(make_server):
    server = make_server()

    async def main():
        client = await tumble.aio.connect(server.address)
        with pytest.raises(tumble.ServerError) as unknown:
            await client.remove("nobody")
        assert unknown.value.code == "UNKNOWN_BODY" and unknown.value.request_id == 2
        with pytest.raises(ValueError):
            await client.force("crate", (1, 2))
        server.stop()
        with pytest.raises(tumble.ConnectionLost):
            await client.bodies()
        await client.close()

    run(main())
