"""What the Python client's tests share: the real tumbled of the build tree,
started on a free port of 127.0.0.1 (--listen 127.0.0.1:0 --port-file), and
the package from clients/python/src.

ctest sets TUMBLED (the binary), TUMBLE_SCENES (scenes/), PROTOC and
TUMBLE_PYTHON_SOURCE (clients/python); the tests import the package from
that source tree.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from typing import Iterator, List, Optional

import pytest

SOURCE = os.environ.get("TUMBLE_PYTHON_SOURCE",
                        os.path.join(os.path.dirname(__file__), "..", "..", "clients", "python"))
sys.path.insert(0, os.path.join(SOURCE, "src"))

STARTUP_SECONDS = 30  # generous: sanitizer builds start slowly
STOP_SECONDS = 30

# No gravity: a 2 kg crate at rest at the origin, a 1 kg ball 3 m along +x,
# and a capsule spinning about y at -3 m.
FREE_SCENE = {"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2.0},
    {"name": "ball", "shape": {"sphere": {"radius": 0.3}}, "mass": 1.0, "position": [3, 0, 0]},
    {"name": "pill", "shape": {"capsule": {"radius": 0.2, "half_height": 0.4}}, "mass": 1.5,
     "position": [-3, 0, 0], "angular_velocity": [0, 0.5, 0]}]}


class Tumbled:
    """A tumbled child process on a free port of 127.0.0.1; stop() checks it exits 0 on SIGTERM."""

    def __init__(self, scene: dict, args: Optional[List[str]] = None) -> None:
        self._dir = tempfile.TemporaryDirectory(prefix="tumble-python-")
        scene_path = os.path.join(self._dir.name, "scene.json")
        with open(scene_path, "w") as f:
            json.dump(scene, f)
        port_file = os.path.join(self._dir.name, "port")
        self.log_path = os.path.join(self._dir.name, "tumbled.log")
        tumbled = os.environ.get("TUMBLED")
        if not tumbled:
            pytest.fail("TUMBLED is not set: run these tests through ctest (label python)")
        with open(self.log_path, "wb") as log:
            self.process = subprocess.Popen(
                [tumbled, "--listen", "127.0.0.1:0", "--port-file", port_file, "--scene", scene_path,
                 *(args or [])], stdout=log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + STARTUP_SECONDS
        while True:
            if self.process.poll() is not None:
                pytest.fail(f"tumbled exited with {self.process.returncode} at startup:\n{self.log()}")
            # The port file is written whole once tumbled listens.
            text = open(port_file).read().strip() if os.path.exists(port_file) else ""
            if text.isdigit():
                self.port = int(text)
                break
            if time.monotonic() > deadline:
                self.process.kill()
                pytest.fail(f"tumbled wrote no port within {STARTUP_SECONDS} s:\n{self.log()}")
            time.sleep(0.02)  # polling the port file, the only thing tumbled offers to wait on
        self.address = f"127.0.0.1:{self.port}"

    def log(self) -> str:
        with open(self.log_path, errors="replace") as f:
            return f.read()

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(STOP_SECONDS)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
                pytest.fail(f"tumbled did not stop on SIGTERM:\n{self.log()}")
            assert self.process.returncode == 0, f"tumbled exited with {self.process.returncode}:\n{self.log()}"
        self._dir.cleanup()


@pytest.fixture
def server() -> Iterator[Tumbled]:
    """tumbled on FREE_SCENE at 240 Hz."""
    process = Tumbled(FREE_SCENE)
    yield process
    process.stop()


@pytest.fixture
def make_server() -> Iterator:
    """Starts tumbled on a scene and arguments of the test's choosing; stopped after the test."""
    started: List[Tumbled] = []

    def make(scene: dict = FREE_SCENE, args: Optional[List[str]] = None) -> Tumbled:
        started.append(Tumbled(scene, args))
        return started[-1]

    yield make
    for process in started:
        process.stop()


def frames_until(subscription, tick):
    """The frames of a stream by tick, up to the frame of `tick` (a slow reader may miss some before it)."""
    import tumble  # the package under test, on the path the fixtures set up
    out = {}
    while tick not in out:
        item = subscription.next(timeout=30)
        if isinstance(item, tumble.Frame):
            out[item.tick] = item
    return out
