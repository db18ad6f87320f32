#!/usr/bin/env python3
"""Lockstep round trips a second from Python: spawns --bodies spheres (1 m
apart, never touching) into the world of a running tumbled, pauses it, and
calls Client.step(1, forces={first body: ...}) for --seconds, each answered
with the frame of every body. Prints the rate and the median and 99th
percentile of one round trip.

    tumbled --max-commands-per-second 100000 &
    python3 clients/python/examples/lockstep_rate.py --server 127.0.0.1:7400 --bodies 1000

tumbled's default --max-commands-per-second (1000) would refuse the
requests beyond 1000 a second with RATE_LIMITED.
"""

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import numpy as np  # noqa: E402

import tumble  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--server", default=None, help="HOST:PORT (default: $TUMBLE_SERVER or 127.0.0.1:7400)")
    parser.add_argument("--bodies", type=int, default=1)
    parser.add_argument("--seconds", type=float, default=5.0)
    args = parser.parse_args()
    with tumble.connect(args.server) as client:
        client.pause()
        side = int(np.ceil(np.sqrt(args.bodies)))
        if args.bodies < 1:
            parser.error("--bodies must be at least 1")
        # Nameless, so that the script can run again against the same server.
        ids = [client.spawn("", sphere=0.25, at=(float(i % side), 100.0, float(i // side)))
               for i in range(args.bodies)]
        first = ids[0]
        frame = client.step(1)
        times = []
        end = time.perf_counter() + args.seconds
        while True:
            began = time.perf_counter()
            frame = client.step(1, forces={first: (1.0, 0.0, 0.0)})
            done = time.perf_counter()
            times.append(done - began)
            if done > end:
                break
        ms = np.array(times) * 1e3
        print(f"bodies={len(frame)} steps={len(times)} steps_per_s={len(times) / ms.sum() * 1e3:.0f} "
              f"round_trip_ms_p50={np.median(ms):.3f} round_trip_ms_p99={np.percentile(ms, 99):.3f}")


if __name__ == "__main__":
    main()
