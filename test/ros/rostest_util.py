"""Helpers shared by the package's Python rostest checks."""
import time

import rospy


def wait_for(pred, timeout, what, poll=0.002):
    """Poll pred() until it is true; AssertionError naming `what` after `timeout` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end and not rospy.is_shutdown():
        if pred():
            return
        time.sleep(poll)
    raise AssertionError("timed out after %.1f s waiting for %s" % (timeout, what))
