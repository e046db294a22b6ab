"""preadaptive_mrac.studies.noise: which onsets count as detections and which as false onsets."""

import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import noise


class TestClassify(unittest.TestCase):
    def test_detections_within_the_window_after_each_switch(self):
        s0, s1 = noise.SWITCHES[0], noise.SWITCHES[1]
        events = [
            {'type': 'onset', 't': s0 + 0.1},
            {'type': 'onset', 't': s0 + 0.2},  # a second onset after the same switch
            {'type': 'recovered', 't': s0 + 1.0},
            {'type': 'onset', 't': s1 + noise.WINDOW},  # the window's end counts
            {'type': 'onset', 't': s1 + noise.WINDOW + 0.01},  # false
            {'type': 'onset', 't': 1.0},  # false, before any switch
            {'type': 'ignored_onset', 't': 2.0},
        ]
        self.assertEqual(noise.classify({'events': events}), (2, 2))

    def test_no_events(self):
        self.assertEqual(noise.classify({'events': []}), (0, 0))


if __name__ == '__main__':
    unittest.main()
