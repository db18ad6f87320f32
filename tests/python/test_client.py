"""tumble.Client against the real tumbled: listing, pushing, editing, the
clock, stats, and its errors (ServerError, ConnectionLost, ValueError before
anything is sent)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tumble

# A constant force on a free body: semi-implicit Euler (physics/src/
# integrator.h) gives v_n = n a dt and x_n = a dt^2 n (n + 1) / 2.
DT = 1 / 240


def test_bodies_lists_the_scene(server):
    with tumble.connect(server.address) as client:
        assert client.welcome.role == "controller"
        bodies = client.bodies()
    assert [b.name for b in bodies] == ["crate", "ball", "pill"]
    crate, ball, pill = bodies
    assert (crate.id, crate.shape, crate.size, crate.motion, crate.mass) == (0, "box", (0.5, 0.5, 0.5), "dynamic", 2.0)
    assert ball.shape == "sphere" and ball.size == (0.3,)
    assert pill.shape == "capsule" and pill.size == (0.2, 0.4)
    np.testing.assert_allclose(ball.position, [3, 0, 0])
    np.testing.assert_allclose(crate.orientation, [1, 0, 0, 0])
    np.testing.assert_allclose(pill.angular_velocity, [0, 0.5, 0])
    assert not crate.asleep


def test_the_address_and_token_come_from_the_environment(make_server, monkeypatch):
    server = make_server(args=["--token", "sesame"])
    monkeypatch.setenv("TUMBLE_SERVER", server.address)
    with pytest.raises(tumble.ServerError) as refused:
        tumble.connect()
    assert refused.value.code == "UNAUTHENTICATED"
    monkeypatch.setenv("TUMBLE_TOKEN", "sesame")
    with tumble.connect() as client:
        assert client.welcome.body_count == 3


def test_a_force_for_ticks_moves_the_crate_as_the_integrator_says(server):
    with tumble.connect(server.address) as client:
        client.pause()
        tick = client.force("crate", np.array([10.0, 0, 0]), ticks=24)
        assert tick == client.stats()["tick"] + 1
        frame = client.step(48, bodies=["crate"])
    a = 10 / 2
    # 24 ticks of force, then 24 at the speed it reached.
    v = 24 * a * DT
    x = a * DT * DT * 24 * 25 / 2 + 24 * v * DT
    crate = frame["crate"]
    assert crate.position[0] == pytest.approx(x, rel=1e-5)
    assert crate.linear_velocity[0] == pytest.approx(v, rel=1e-5)


def test_spawn_set_remove_and_clear(server):
    with tumble.connect(server.address) as client:
        client.pause()
        rock = client.spawn("rock", sphere=0.25, mass=3, at=(0, 5, 0), linear_velocity=(1, 0, 0))
        assert rock == 3
        listed = {b.name: b for b in client.bodies()}
        assert listed["rock"].id == rock and listed["rock"].mass == 3.0
        np.testing.assert_allclose(listed["rock"].linear_velocity, [1, 0, 0])
        client.set(rock, position=(1, 2, 3), orientation=(0, 1, 0, 0))
        frame = client.step(1, bodies=[rock])
        np.testing.assert_allclose(frame[rock].position, [1 + DT, 2, 3], atol=1e-6)
        np.testing.assert_allclose(np.abs(frame["rock"].orientation), [0, 1, 0, 0], atol=1e-6)
        client.force("rock", (0, 9, 0), persistent=True)
        client.torque("crate", (0, 0, 1), persistent=True)
        client.clear()
        frame = client.step(1, bodies=["rock", "crate"])
        np.testing.assert_allclose(frame["rock"].linear_velocity, [1, 0, 0], atol=1e-6)
        np.testing.assert_allclose(frame["crate"].angular_velocity, [0, 0, 0], atol=1e-9)
        client.remove("rock")
        assert "rock" not in [b.name for b in client.bodies()]


def test_impulse_at_a_point_spins_the_body(server):
    with tumble.connect(server.address) as client:
        client.pause()
        client.impulse("ball", (0, 1, 0), at=(0.3, 0, 0), local=True)
        (ball,) = [b for b in client.bodies() if b.name == "ball"]
    np.testing.assert_allclose(ball.linear_velocity, [0, 1, 0])
    # L = r x J = (0.3, 0, 0) x (0, 1, 0) = 0.3 about z; a solid sphere's I = 2/5 m r^2.
    assert ball.angular_velocity[2] == pytest.approx(0.3 / (0.4 * 1.0 * 0.3 * 0.3))


def test_the_clock_pause_resume_reset_and_tick_rate(server):
    with tumble.connect(server.address) as client:
        paused_at = client.pause()
        stats = client.stats()
        assert stats["paused"] and stats["tick"] == paused_at
        assert client.step(5).tick == paused_at + 5
        client.spawn("rock", box=(0.1, 0.1, 0.1))
        client.reset()
        assert [b.name for b in client.bodies()] == ["crate", "ball", "pill"]
        assert client.tick_rate(120) == paused_at + 6
        assert client.stats()["tick_rate_hz"] == 120
        assert client.resume() == paused_at + 6
        assert not client.stats()["paused"]


def test_a_refused_request_raises_server_error_with_code_and_request_id(server):
    with tumble.connect(server.address) as client:
        with pytest.raises(tumble.ServerError) as unknown:
            client.force("nobody", (1, 0, 0))
        assert unknown.value.code == "UNKNOWN_BODY"
        assert "nobody" in unknown.value.message
        assert unknown.value.request_id == 2  # Hello was 1
        with pytest.raises(tumble.ServerError) as running:
            client.step()
        assert running.value.code == "FAILED_PRECONDITION"
        # The connection goes on.
        assert len(client.bodies()) == 3


@pytest.mark.parametrize("call, message", [
    (lambda c: c.force("crate", (1, 0)), "force must be 3 numbers"),
    (lambda c: c.force("crate", (1, 0, math.nan)), "force[2] must be finite"),
    (lambda c: c.force("crate", (1, 0, 0), duration=1, persistent=True), "at most one of duration"),
    (lambda c: c.force("", (1, 0, 0)), "must not be empty"),
    (lambda c: c.force(1.5, (1, 0, 0)), "an id (int) or a name (str)"),
    (lambda c: c.impulse("crate", (1, 0, 0), local=True), "needs a point"),
    (lambda c: c.spawn("rock"), "exactly one shape"),
    (lambda c: c.spawn("12", sphere=1), "digits only"),
    (lambda c: c.set("crate", orientation=(1, 1, 0, 0)), "unit quaternion"),
    (lambda c: c.set("crate"), "at least one of"),
    (lambda c: c.tick_rate(0), "from 1 to 10000"),
    (lambda c: c.step(0), "from 1 to 1000000"),
    (lambda c: c.step(1, forces=[("crate", (1, 0, 0))]), "map bodies to vectors"),
    (lambda c: c.subscribe(encoding="zip"), "'full', 'quantized' or 'delta'"),
    (lambda c: c.subscribe(events=["boom"]), "not one of"),
])
def test_bad_arguments_raise_value_error_before_anything_is_sent(server, call, message):
    with tumble.connect(server.address) as client:
        with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
            call(client)
        # Nothing was framed: the next request is still the second of the connection.
        with pytest.raises(tumble.ServerError) as unknown:
            client.remove("nobody")
        assert unknown.value.request_id == 2


def test_a_server_that_goes_away_raises_connection_lost(make_server):
    server = make_server()
    client = tumble.connect(server.address)
    server.stop()
    with pytest.raises(tumble.ConnectionLost):
        client.bodies()
    with pytest.raises(tumble.ConnectionLost):
        client.stats()


def test_a_reply_that_does_not_come_raises_timeout_error(server):
    with tumble.connect(server.address, timeout=0.5) as client:
        client.pause()
        # A Step of a million ticks takes far longer than half a second.
        with pytest.raises(TimeoutError):
            client.step(1_000_000)
