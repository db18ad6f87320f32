"""A client of tumbled, the tumble rigid-body simulation server.

    import tumble

    with tumble.connect("127.0.0.1:7400") as client:
        print([b.name for b in client.bodies()])
        client.force("crate", (10, 0, 0), duration=0.5)
        for frame in client.subscribe(bodies=["crate"], rate=30):
            print(frame.tick, frame["crate"].position)

        client.pause()
        frame = client.step(1, forces={"crate": (0, 20, 0)})  # one round trip a step

tumble.aio has the same API with async/await. See clients/python/README.md.
"""

from tumble._client import Client, Subscription, connect
from tumble._core import Body, BodyLike, Event, Vector, Welcome
from tumble._errors import ConnectionLost, Error, ServerError, StepCutShort
from tumble._poses import BodyState, Frame

__version__ = "0.1.0"
"""The version of this package."""

__all__ = ["connect", "Client", "Subscription", "Body", "BodyLike", "BodyState", "Event", "Frame", "Vector",
           "Welcome", "Error", "ServerError", "ConnectionLost", "StepCutShort", "__version__"]
