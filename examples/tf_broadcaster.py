#!/usr/bin/env python
"""Publishing a tf marker in Python: the course's broadcaster (section 4.2.2.3) on urdftk's ``tf``.

Only the rospy lines changed: ``rospy.init_node`` is gone (no master), ``rospy.Time.now()`` is
``tf.Time.now()``, and ``rospy.Rate(10)`` / ``rospy.is_shutdown()`` are a 10 Hz loop that stops
after ``--duration`` seconds (default: until Ctrl-C). The frame goes out on the default transport
(``URDFTK_TRANSPORT``: zenoh by default, or inproc).

    python examples/tf_broadcaster.py --duration 5
"""

from __future__ import annotations

import argparse
import threading

import tf

my_FrameName = "my_frame"


def myPublishFunction(duration=None, stop=None, transport=None):
    my_transformBroadcaster = tf.TransformBroadcaster(transport)

    stop = stop or threading.Event()  # rospy.init_node(...) and rospy.is_shutdown()
    if duration is not None:
        threading.Timer(duration, stop.set).start()
    period = 1.0 / 10  # rate = rospy.Rate(10)

    x = 0.2
    y = 0.25
    z = 1
    roll = 0.25
    pitch = 0.1
    yaw = 0.2

    while not stop.is_set():
        my_transformBroadcaster.sendTransform((x, y, z),
                                              tf.transformations.quaternion_from_euler(roll, pitch, yaw),
                                              tf.Time.now(), my_FrameName, "world")  # fmt: skip
        stop.wait(period)  # rate.sleep()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=None, help="stop after this many seconds")
    args = parser.parse_args()
    try:  # noqa: SIM105 - the course's structure
        myPublishFunction(args.duration)
    except KeyboardInterrupt:  # was rospy.ROSInterruptException
        pass
