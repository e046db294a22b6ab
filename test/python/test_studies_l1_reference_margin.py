"""preadaptive_mrac.studies.l1_reference_margin: the design, the margin finder, the loops."""

import math
import unittest

import numpy as np

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import l1_reference_margin as lm

# K and P as `preadapt_sim --scenario 1 --mode l1 --json` prints them (the C++ design).
K_CPP = [-1.0000000000000002, -1.1466677945938641, -1.2934809849247204]
P_CPP = [
    [2.196136863050217, 1.652793262126804, 0.4025380472047101],
    [1.652793262126804, 2.4701167185579607, 0.5777124168975589],
    [0.4025380472047101, 0.5777124168975589, 0.5086345726988919],
]


class TestL1ReferenceMargin(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.d = lm.load_design()
        cls.regimes, cls.r = lm.scenario_regimes()
        cls.x_eq = lm.l1_equilibrium(cls.d, cls.r)

    def test_design_is_the_controllers(self):
        np.testing.assert_allclose(self.d.K, K_CPP, atol=1e-9)
        np.testing.assert_allclose(self.d.P, P_CPP, atol=1e-9)
        self.assertEqual([th[0] for _, _, th in self.regimes], [0.1, 1.0, 2.0, 4.0])
        # the tracked steady state: alpha = r, and A_r x* + b_ref r = 0
        self.assertAlmostEqual(self.x_eq[1], self.r, places=12)

    def test_delay_margin_of_known_loops(self):
        tau, wc, pm = lm.delay_margin(lambda s: 5.0 / s)
        self.assertAlmostEqual(wc, 5.0, places=6)
        self.assertAlmostEqual(pm, 90.0, places=4)
        self.assertAlmostEqual(tau, math.pi / 10.0, places=6)
        # 2 / (s + 1): w_c = sqrt(3), PM = 120 deg
        tau, wc, pm = lm.delay_margin(lambda s: 2.0 / (s + 1.0))
        self.assertAlmostEqual(tau, 2.0 * math.pi / 3.0 / math.sqrt(3.0), places=6)
        self.assertTrue(math.isinf(lm.delay_margin(lambda s: 0.5 / (s + 1.0))[0]))

    def test_fast_loop_closes_like_the_reference_without_delay(self):
        th, om = 2.0 * np.ones(3), 20.0
        ref, fast = lm.reference_loop(self.d, om, th), lm.fast_adaptation_loop(self.d, om, th)
        for s in (0.3 + 1.0j, -2.0 + 5.0j, 40.0j):
            c = om / (s + om)
            self.assertAlmostEqual(abs((1 - c) * (1 + fast(s)) - (1 + ref(s))), 0.0, places=12)

    def test_reference_margin_by_frequency_eigenvalues_and_simulation(self):
        th = 0.1 * np.ones(3)
        self.assertTrue(lm.reference_closed_loop_stable(self.d, 150.0, th))
        tau = lm.delay_margin(lm.reference_loop(self.d, 150.0, th))[0]
        self.assertTrue(0.88 < tau < 0.90, tau)
        for scale in (1.0, 4.0):  # |L_ref| < 1 everywhere: any delay holds
            L = lm.reference_loop(self.d, 150.0, scale * np.ones(3))
            self.assertTrue(math.isinf(lm.delay_margin(L)[0]))
        n = int(tau / self.d.dt)
        rho = [
            lm.spectral_radius(lm.reference_discrete(self.d, 150.0, th, N)) for N in (n - 1, n + 2)
        ]
        self.assertLess(rho[0], 1.0)
        self.assertGreater(rho[1], 1.0)
        first, last = lm.simulate_reference(self.d, 150.0, th, n - 20, 60.0)
        self.assertLess(last, 0.5 * first)
        first, last = lm.simulate_reference(self.d, 150.0, th, n + 20, 60.0)
        self.assertGreater(last, first)

    def test_fast_loop_margin_is_set_by_the_filter(self):
        kb = float(self.d.K @ self.d.B)
        for om in (20.0, 150.0):
            tau = lm.delay_margin(lm.fast_adaptation_loop(self.d, om, 0.1 * np.ones(3)))[0]
            self.assertAlmostEqual(tau * (om + kb) / (math.pi / 2), 1.0, delta=0.05)

    def test_linearised_l1_limits(self):
        th = 0.1 * np.ones(3)
        # predictor driven by the command: fast adaptation tends to the fast-adaptation loop
        L, stable = lm.l1_loop(self.d, 20.0, 1e8, th, self.x_eq, th)
        self.assertTrue(stable)
        fast = lm.delay_margin(lm.fast_adaptation_loop(self.d, 20.0, th))[0]
        self.assertAlmostEqual(lm.delay_margin(L, points=4000)[0] / fast, 1.0, delta=0.01)
        # driven by the applied u_ad: the reference system at any Gamma
        L, stable = lm.l1_loop(self.d, 20.0, 1e4, th, self.x_eq, th, applied=True)
        ref = lm.delay_margin(lm.reference_loop(self.d, 20.0, th))[0]
        self.assertAlmostEqual(lm.delay_margin(L, points=4000)[0], ref, places=4)

    def test_sampled_l1_matches_continuous_and_euler_limit(self):
        th = 0.1 * np.ones(3)
        d = lm.load_design()
        d.dt = 1e-4
        Ao, Bo, Co = lm.l1_state_space(d, 150.0, 1e4, th, self.x_eq, th)
        growth = np.linalg.eigvals(Ao + np.outer(Bo, Co)).real.max()
        rho = lm.spectral_radius(lm.l1_linearised(d, 150.0, 1e4, th, self.x_eq, th, 0))
        self.assertAlmostEqual(math.log(rho) / d.dt, growth, delta=0.05)
        # at dt = 1 ms forward Euler destabilises the adaptation mode without any delay
        d.dt = 1e-3
        self.assertLess(
            lm.spectral_radius(lm.l1_linearised(d, 150.0, 1e4, th, self.x_eq, th, 0)), 1.0
        )
        self.assertGreater(
            lm.spectral_radius(lm.l1_linearised(d, 150.0, 1e5, th, self.x_eq, th, 0)), 1.0
        )


if __name__ == '__main__':
    unittest.main()
