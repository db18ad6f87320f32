"""The real tumbled on an ephemeral port of 127.0.0.1, for the interop tests.

TumbledServer(tumbled, scene) starts it with --listen 127.0.0.1:0 and
--port-file, waits for the port, and on exit from the `with` block stops it
with SIGTERM and checks that it exited 0. Its log goes to a file in a
temporary directory, printed when something fails.
"""

import os
import signal
import subprocess
import tempfile
import time


class TumbledServer:
    """A tumbled child process serving `scene`; use as a context manager."""

    STARTUP_SECONDS = 30  # generous: sanitizer builds start slowly
    STOP_SECONDS = 30

    def __init__(self, tumbled, scene):
        self._tumbled = tumbled
        self._scene = scene
        self._dir = tempfile.TemporaryDirectory(prefix="tumble-interop-")
        self._log_path = os.path.join(self._dir.name, "tumbled.log")
        self._process = None
        self.port = 0

    def __enter__(self):
        port_file = os.path.join(self._dir.name, "port")
        with open(self._log_path, "wb") as log:
            self._process = subprocess.Popen(
                [self._tumbled, "--listen", "127.0.0.1:0", "--port-file", port_file, "--scene", self._scene],
                stdout=log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + self.STARTUP_SECONDS
        while time.monotonic() < deadline:
            if self._process.poll() is not None:
                raise RuntimeError(f"tumbled exited with {self._process.returncode} at startup:\n{self.log()}")
            # The port file is written whole once tumbled listens; until then
            # it is missing or empty.
            if os.path.exists(port_file):
                with open(port_file) as f:
                    text = f.read().strip()
                if text.isdigit():
                    self.port = int(text)
                    return self
            time.sleep(0.05)
        self._process.kill()
        raise RuntimeError(f"tumbled did not write its port within {self.STARTUP_SECONDS} s:\n{self.log()}")

    def __exit__(self, exc_type, exc, tb):
        try:
            if self._process.poll() is None:
                self._process.send_signal(signal.SIGTERM)
                try:
                    self._process.wait(self.STOP_SECONDS)
                except subprocess.TimeoutExpired:
                    self._process.kill()
                    self._process.wait()
                    raise RuntimeError(f"tumbled did not stop on SIGTERM:\n{self.log()}")
            if exc_type is None and self._process.returncode != 0:
                raise RuntimeError(f"tumbled exited with {self._process.returncode}:\n{self.log()}")
        finally:
            if exc_type is not None:
                print(f"tumbled log:\n{self.log()}")
            self._dir.cleanup()
        return False

    def log(self):
        with open(self._log_path, errors="replace") as f:
            return f.read()
