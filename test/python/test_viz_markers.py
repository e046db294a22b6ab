"""preadaptive_mrac.viz.markers: a JSBSim run's truth (its conditions record with the
engine's rows) adds the pitch attitude, flight path angle, airspeed and altitude to rviz's text
and turns the velocity frame by the whole angle of attack; a linear run's truth adds nothing.
Stand-in messages, no master."""

import math
import threading
import types
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.viz import markers

LINEAR = ['u_applied', 'effectiveness', 'w_gust', 'plant_limited']
JSBSIM = LINEAR + ['pitch', 'airspeed', 'altitude', 'flight_path']


def truth(names, values):
    return types.SimpleNamespace(
        condition_names=names, conditions=values, theta=[], envelope_exit=''
    )


def state(t=1.0, alpha=0.01):
    return types.SimpleNamespace(t=t, alpha=alpha, elevator=0.0, theta_pitch=0.3, step=1)


def viz():
    v = object.__new__(markers.VizMarkers)
    v.world, v.body, v.velocity = 'world', 'body', 'velocity'
    v.altitude0 = None
    v.lock = threading.Lock()
    return v


class TestFlightText(unittest.TestCase):
    def test_linear_truth_has_no_flight(self):
        self.assertIsNone(markers.flight_of(truth(LINEAR, [0, 1, 0, 0])))
        self.assertIsNone(markers.flight_of(None))
        texts = [m.text for m in viz().texts(state(), None, truth(LINEAR, [0, 1, 0, 0]), None)]
        self.assertFalse(any('airspeed' in t for t in texts), texts)

    def test_jsbsim_truth_shows_attitude_airspeed_altitude(self):
        v = viz()
        first = truth(JSBSIM, [0, 1, 0, 0, 0.0777, 236.06, 12192.0, 0.0])
        later = truth(JSBSIM, [0, 1, 0, 0, math.radians(10.0), 230.0, 12250.5, math.radians(5.0)])
        self.assertEqual(markers.flight_of(first)['airspeed'], 236.06)
        v.texts(state(), None, first, None)
        texts = [m.text for m in v.texts(state(), None, later, None) if m.text]
        self.assertIn('pitch +10.00 deg, flight path +5.00 deg', texts)
        self.assertIn('airspeed 230.0 m/s, altitude 12250 m (+58.5 m)', texts)


if __name__ == '__main__':
    unittest.main()
