"""Helpers shared by the package's Python rostest checks."""
import signal
import subprocess
import threading
import time
import unittest

import rospy
from catkin.find_in_workspaces import find_in_workspaces


def wait_for(pred, timeout, what, poll=0.002):
    """Poll pred() until it is true; AssertionError naming `what` after `timeout` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end and not rospy.is_shutdown():
        if pred():
            return
        time.sleep(poll)
    raise AssertionError("timed out after %.1f s waiting for %s" % (timeout, what))


def signal_node(node, sig, timeout, what):
    """Send `sig` to the process of the launched node `node` (its pid asked through the
    master and the node's own API) and wait until it has exited (gone, or a zombie of
    roslaunch's); AssertionError naming `what` after `timeout` seconds. The pid."""
    import os
    import xmlrpc.client

    import rosgraph
    import rosnode

    caller = rospy.get_name()
    uri = rosnode.get_api_uri(rosgraph.Master(caller), node)
    pid = xmlrpc.client.ServerProxy(uri).getPid(caller)[2]
    os.kill(pid, sig)
    wait_for(lambda: _exited(pid), timeout, what)
    return pid


def _exited(pid):
    """True when process pid is gone or a zombie. Reading its stat file is the one check: the
    process can be reaped between a test for the file and the read (a race that raised
    FileNotFoundError instead of answering 'gone')."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split()[2] == "Z"
    except (FileNotFoundError, ProcessLookupError):
        return True


def wait_connected(sub, timeout, publisher_topic=None):
    """Wait until `sub` is connected to every publisher the master lists for its topic, once
    the topic `publisher_topic` (default: sub's own) has a publisher at all: a subscriber set
    up before a plant starts then misses nothing of the run (the plant waits only for its state
    subscribers, so a topic the test needs besides can otherwise connect too late)."""
    import rosgraph

    master = rosgraph.Master(rospy.get_name())

    def publishers(topic):
        for name, nodes in master.getSystemState()[0]:
            if name == topic:
                return nodes
        return []

    wait_for(
        lambda: publishers(rospy.resolve_name(publisher_topic or sub.resolved_name)),
        timeout,
        "a publisher of %s" % (publisher_topic or sub.resolved_name),
        poll=0.05,
    )
    wait_for(
        lambda: sub.get_num_connections() >= len(publishers(sub.resolved_name)),
        timeout,
        "%s connected to its publishers" % sub.resolved_name,
        poll=0.01,
    )


def subscribe_loop(test):
    """Subscribe controller/elevator_cmd (first, so that the command connection is up before a
    plant that waits for this node's state subscription starts) and plant/state, unbounded and
    tcpNoDelay, to test.on_cmd and test.on_state; kept as test.cmd_sub and test.state_sub."""
    from preadaptive_mrac.msg import ElevatorCommand, PlantState

    test.cmd_sub = rospy.Subscriber(
        "controller/elevator_cmd", ElevatorCommand, test.on_cmd, queue_size=None, tcp_nodelay=True
    )
    test.state_sub = rospy.Subscriber(
        "plant/state", PlantState, test.on_state, queue_size=None, tcp_nodelay=True
    )


def read_episodes(path):
    """The `episodes:` count of a weights file, or None."""
    with open(path) as f:
        for line in f:
            if line.startswith("episodes:"):
                return int(line.split(":")[1])
    return None


class NodeProcessTest(unittest.TestCase):
    """A test that starts the package's nodes itself (so it can SIGKILL and restart them) and
    keeps what it receives with the monotonic time of arrival."""

    PKG = "preadaptive_mrac"

    def setUp(self):
        self.lock = threading.Lock()
        self.procs = []

    def tearDown(self):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
                p.wait(10)

    def add(self, lst, m):
        with self.lock:
            lst.append((time.monotonic(), m))

    def after(self, lst, t0):
        with self.lock:
            return [m for t, m in lst if t > t0]

    def start(self, node, name):
        # The devel space's binary (rosrun would ask which one when build dirs sit in the
        # source tree); started directly, so SIGKILL hits the node itself.
        exe = find_in_workspaces(["libexec"], project=self.PKG, path=node, first_match_only=True)
        self.assertTrue(exe, "%s not found in the workspace" % node)
        p = subprocess.Popen([exe[0], "__name:=" + name])
        self.procs.append(p)
        return p

    def kill(self, p):
        p.send_signal(signal.SIGKILL)
        p.wait(10)
        return time.monotonic()
