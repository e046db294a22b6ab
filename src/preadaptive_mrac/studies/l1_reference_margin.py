"""Time-delay margin of the L1 reference system, and of the loop fast L1 adaptation actually
tends to (docs/research/l1.md, "Time-delay margin and the reference system").

The plant is x_dot = A x + B (u(t - tau) + theta^T x) + B1r r, the controller u = -K x + u_ad
(src/core/control/l1/l1_law.cpp, k0 = 0). Three loops, each broken at the plant input (where
plant.actuator.delay acts), G_theta(s) = (sI - A - B theta^T)^-1 B, C(s) = omega / (s + omega):

- reference system (the estimate equals the true uncertainty, u_ad = -C(s) theta^T x):
      L_ref(s) = (K + C(s) theta^T) G_theta(s)
- fast-adaptation limit (the predictor is driven by the commanded u_ad while the plant gets the
  delayed u, so the prediction error sees sigma = theta^T x + u(t - tau) - u(t), and an
  adaptation fast enough to cancel it feeds that through C(s)): the characteristic equation
  (1 - C) + e^(-s tau) [C + (K + C theta^T) G_theta] = 0, i.e. the loop
      L_fast(s) = [C(s) + (K + C(s) theta^T) G_theta(s)] / (1 - C(s))
  Without delay both give the same closed loop; with a delay they do not.
- l1 itself, linearised about a regime's equilibrium (x*, theta_hat*) in discrete time exactly
  as l1_law.cpp runs it (RK4 plant with the input held, RK4 predictor, the filter's
  discretisation, forward-Euler adaptation), the delay as whole samples. Only s = x*^T
  theta_hat moves the loop, at the effective rate Gamma |x*|^2.

Delay margins: continuous loops from the crossovers (|L(jw)| = 1, margin = min PM / w_c); the
discrete ones from the spectral radius of the delayed closed loop, bisected on whole samples.
"""

import argparse
import json
import math
import os
import subprocess

import numpy as np
import yaml

from ..paths import package_root, tool_dir

DT = 0.001


class Design:
    """A, B of the plant, K of the LQR, A_r = A - B K, P of A_r^T P + P A_r = -I, the sample
    time dt."""

    def __init__(self, A, B, K, P, dt=DT):
        self.A = np.asarray(A, float)
        self.B = np.asarray(B, float)
        self.K = np.asarray(K, float)
        self.Ar = self.A - np.outer(self.B, self.K)
        self.P = np.asarray(P, float)
        self.dt = dt


def load_design(plant=None, controller=None):
    """The design of config/plant/b747.yaml and config/controller/default.yaml: A and B from the
    plant file, K (Riccati) and P (Lyapunov) as the package's own solvers give them
    (`preadapt_sim --json` of the build, paths.tool_dir())."""
    root = package_root()
    plant = plant or f'{root}/config/plant/b747.yaml'
    controller = controller or f'{root}/config/controller/default.yaml'
    with open(plant) as f:
        p = yaml.safe_load(f)['plant']
    with open(controller) as f:
        c = yaml.safe_load(f)['controller']
    if c['reference_model']['k0'] != 0.0:
        raise ValueError('controller.reference_model.k0 must be 0 for this study')
    tool = os.path.join(tool_dir(), 'preadapt_sim')
    if not os.access(tool, os.X_OK):
        raise FileNotFoundError(f'{tool}: build the package first (K and P come from its solvers)')
    run = subprocess.run(
        [
            tool,
            '--scenario',
            '1',
            '--mode',
            'rac',
            '--plant',
            plant,
            '--controller',
            controller,
            '--json',
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    d = json.loads(run.stdout.strip().splitlines()[-1])
    return Design(p['A'], p['B'], d['K'], d['P'], c['sample_time'])


def scenario_regimes(path=None):
    """[(t_start, t_end, theta)] of a scenario whose theta segments are `scale` x ones, and its
    (single) reference r."""
    path = path or f'{package_root()}/config/scenarios/scenario1.yaml'
    with open(path) as f:
        s = yaml.safe_load(f)['scenario']
    out, t0 = [], 0.0
    for seg in s['theta']:
        out.append((t0, float(seg['until']), float(seg['scale']) * np.ones(3)))
        t0 = float(seg['until'])
    refs = {float(r['r']) for r in s['reference']}
    if len(refs) != 1:
        raise ValueError('this study needs a constant reference')
    return out, refs.pop()


# --- continuous loops -----------------------------------------------------------------------


def _g_theta(d, theta, s):
    return np.linalg.solve(s * np.eye(len(d.B)) - d.A - np.outer(d.B, theta), d.B)


def reference_loop(d, omega, theta):
    """s -> L_ref(s) = (K + C(s) theta^T) G_theta(s)."""

    def L(s):
        c = omega / (s + omega)
        return (d.K + c * theta) @ _g_theta(d, theta, s)

    return L


def fast_adaptation_loop(d, omega, theta):
    """s -> L_fast(s) = [C + (K + C theta^T) G_theta] / (1 - C)."""

    def L(s):
        c = omega / (s + omega)
        return (c + (d.K + c * theta) @ _g_theta(d, theta, s)) / (1.0 - c)

    return L


def l1_state_space(d, omega, gamma, theta, x_eq, theta_hat_eq, applied=False):
    """The continuous-time l1 (dt -> 0) linearised about (x*, theta_hat*), as (Ao, Bo, Co): state
    [dx, dxh, s, y], s = x*^T dtheta_hat, input v (the plant's input, after the delay), output u:
        dx' = A_theta dx + B v                     sigma = theta_hat*^T dx + s
        dxh' = A_r dxh + B (y + sigma)  [command]  or  B (v + K dx + sigma)  [applied]
        s' = -Gamma |x*|^2 (PB)^T (dxh - dx)       y' = omega (-sigma - y)     u = -K dx + y"""
    n = len(d.B)
    m = 2 * n + 2
    sig = np.zeros(m)
    sig[:n] = theta_hat_eq
    sig[2 * n] = 1.0
    ycol = np.zeros(m)
    ycol[2 * n + 1] = 1.0
    Ao = np.zeros((m, m))
    Bo = np.zeros(m)
    Ao[:n, :n] = d.A + np.outer(d.B, theta)
    Bo[:n] = d.B
    Ao[n : 2 * n, n : 2 * n] = d.Ar
    if applied:
        drive = sig.copy()
        drive[:n] += d.K
        Bo[n : 2 * n] = d.B
    else:
        drive = sig + ycol
    Ao[n : 2 * n, :] += np.outer(d.B, drive)
    rate = gamma * float(x_eq @ x_eq)
    pb = d.P @ d.B
    Ao[2 * n, :n] = rate * pb
    Ao[2 * n, n : 2 * n] = -rate * pb
    Ao[2 * n + 1, :] = -omega * (sig + ycol)
    Co = ycol.copy()
    Co[:n] = -d.K
    return Ao, Bo, Co


def l1_loop(d, omega, gamma, theta, x_eq, theta_hat_eq, applied=False):
    """(s -> L(s), stable): l1_state_space's loop broken at the plant input, L = -u/v, and
    whether its undelayed closed loop (v = u) is Hurwitz."""
    Ao, Bo, Co = l1_state_space(d, omega, gamma, theta, x_eq, theta_hat_eq, applied)
    eye = np.eye(len(Bo))
    stable = bool(np.linalg.eigvals(Ao + np.outer(Bo, Co)).real.max() < 0.0)
    return (lambda s: -Co @ np.linalg.solve(s * eye - Ao, Bo)), stable


def reference_closed_loop_stable(d, omega, theta):
    """The undelayed reference system [x; z], z = C(s) theta^T x, u = -K x - z, is Hurwitz."""
    n = len(d.B)
    M = np.zeros((n + 1, n + 1))
    M[:n, :n] = d.A + np.outer(d.B, theta) - np.outer(d.B, d.K)
    M[:n, n] = -d.B
    M[n, :n] = omega * theta
    M[n, n] = -omega
    return bool(np.linalg.eigvals(M).real.max() < 0.0)


def delay_margin(L, w_min=1e-4, w_max=1e5, points=20000):
    """(tau, w_c, pm_deg) of the crossover with the smallest PM / w_c, PM wrapped into
    [0, 360) deg; (inf, None, None) when |L(jw)| never reaches 1 on [w_min, w_max]. Assumes the
    undelayed closed loop is stable: the first imaginary-axis crossing as tau grows is then at a
    crossover, at tau = PM / w_c."""
    ws = np.logspace(math.log10(w_min), math.log10(w_max), points)
    m = np.array([abs(L(1j * w)) for w in ws]) - 1.0
    best = (math.inf, None, None)
    for i in np.where(np.sign(m[:-1]) != np.sign(m[1:]))[0]:
        a, b = ws[i], ws[i + 1]
        for _ in range(60):  # bisection on log w
            c = math.sqrt(a * b)
            if np.sign(abs(L(1j * c)) - 1.0) == np.sign(m[i]):
                a = c
            else:
                b = c
        wc = math.sqrt(a * b)
        pm = (np.angle(L(1j * wc)) + math.pi) % (2.0 * math.pi)
        if pm / wc < best[0]:
            best = (pm / wc, wc, math.degrees(pm))
    return best


# --- discrete loops (l1_law.cpp's sampling) -------------------------------------------------


def rk4_hold(M, dt):
    """Phi, G of classic RK4 over dt for z' = M z + w with w held: Phi = I + h + h^2/2 + h^3/6 +
    h^4/24 (h = M dt), G = dt (I + h/2 + h^2/6 + h^3/24)."""
    h = M * dt
    eye = np.eye(M.shape[0])
    h2 = h @ h
    h3 = h2 @ h
    return eye + h + h2 / 2 + h3 / 6 + h3 @ h / 24, dt * (eye + h / 2 + h2 / 6 + h3 / 24)


def _with_delay(F, u_row, gx, N):
    """The closed loop over one sample with a delay of N samples on u: the state [z; u_k-1 ..
    u_k-N], z' = F z + gx u_applied, u_applied = u_k-N, u_k = u_row z."""
    m = F.shape[0]
    T = np.zeros((m + N, m + N))
    T[:m, :m] = F
    if N == 0:
        T[:m, :m] += np.outer(gx, u_row)
    else:
        T[:m, m + N - 1] = gx
        T[m, :m] = u_row
        for j in range(1, N):
            T[m + j, m + j - 1] = 1.0
    return T


def reference_discrete(d, omega, theta, N):
    """Transition of the sampled reference system with N samples of delay: state [x, y_k-1],
    y_k = a y_k-1 - (1 - a) theta^T x_k, u_k = -K x_k + y_k."""
    n = len(d.B)
    a = math.exp(-omega * d.dt)
    Phi, G = rk4_hold(d.A + np.outer(d.B, theta), d.dt)
    u_row = np.concatenate([-d.K - (1 - a) * theta, [a]])
    F = np.zeros((n + 1, n + 1))
    F[:n, :n] = Phi
    F[n, :] = np.concatenate([-(1 - a) * theta, [a]])
    return _with_delay(F, u_row, np.concatenate([G @ d.B, [0.0]]), N)


def l1_equilibrium(d, r):
    """x* of the tracked steady state (the reference model's): A_r x + b_ref r = 0, k0 = 0."""
    return np.linalg.solve(d.Ar, -np.array([-1.0, 0.0, 0.0]) * r)


def l1_linearised(d, omega, gamma, theta, x_eq, theta_hat_eq, N, applied=False):
    """Transition of l1 (l1_law.cpp) linearised about (x*, theta_hat*) with N samples of delay.
    State [dx, dxh, s, y_k-1], s = x*^T dtheta_hat; dsigma = theta_hat*^T dx + s. The predictor
    is driven by the command u_ad,k as in the controller, or with `applied` by the adaptive part
    the plant received, u_k-N + K x_k (L1Law::advance's u_ad_applied; needs the delay known)."""
    n = len(d.B)
    a = math.exp(-omega * d.dt)
    Phi, G = rk4_hold(d.A + np.outer(d.B, theta), d.dt)
    Phr, Gr = rk4_hold(d.Ar, d.dt)
    pb = d.P @ d.B
    rate = gamma * float(x_eq @ x_eq) * d.dt
    m = 2 * n + 2
    sig = np.zeros(m)  # dsigma_k
    sig[:n] = theta_hat_eq
    sig[2 * n] = 1.0
    y = -(1 - a) * sig  # y_k = a y_k-1 - (1 - a) dsigma_k
    y[2 * n + 1] += a
    u_row = y.copy()
    u_row[:n] -= d.K
    F = np.zeros((m, m))
    F[:n, :n] = Phi
    F[n : 2 * n, n : 2 * n] = Phr  # predictor: Phi_r xh + G_r B (u_ad + sigma_k)
    drive = sig.copy()
    if applied:
        drive[:n] += d.K
    else:
        drive += y
    F[n : 2 * n, :] += np.outer(Gr @ d.B, drive)
    F[2 * n, :] = np.zeros(m)  # s' = s - dt Gamma |x*|^2 (PB)^T (dxh - dx)
    F[2 * n, 2 * n] = 1.0
    F[2 * n, :n] += rate * pb
    F[2 * n, n : 2 * n] -= rate * pb
    F[2 * n + 1, :] = y
    gx = np.zeros(m)
    gx[:n] = G @ d.B
    if applied:
        gx[n : 2 * n] = Gr @ d.B
    return _with_delay(F, u_row, gx, N)


def simulate_reference(d, omega, theta, N, duration, x0=(0.0, 0.1, 0.0)):
    """Time simulation of the sampled reference system with N samples of delay on u (the
    delay line starts at 0) from x0: the largest |x| over the first and the last second."""
    n = len(d.B)
    a = math.exp(-omega * d.dt)
    Phi, G = rk4_hold(d.A + np.outer(d.B, theta), d.dt)
    gb = G @ d.B
    x = np.array(x0, float)
    y = 0.0
    line = [0.0] * (N + 1)
    steps = int(round(duration / d.dt))
    sec = int(round(1.0 / d.dt))
    first = last = 0.0
    for k in range(steps):
        y = a * y - (1 - a) * float(theta @ x)
        line[k % (N + 1)] = -float(d.K @ x) + y  # u_k; u_k-N sits in the next slot
        x = Phi @ x + gb * line[(k + 1) % (N + 1)]
        if k < sec:
            first = max(first, float(np.abs(x[:n]).max()))
        elif k >= steps - sec:
            last = max(last, float(np.abs(x[:n]).max()))
    return first, last


def spectral_radius(T):
    return float(np.abs(np.linalg.eigvals(T)).max())


def discrete_margin(transition, max_steps):
    """Largest N in [0, max_steps] with transition(N) Schur-stable, by bisection (one boundary
    assumed); -1 when N = 0 is unstable, max_steps when it holds there."""
    if spectral_radius(transition(0)) >= 1.0:
        return -1
    if spectral_radius(transition(max_steps)) < 1.0:
        return max_steps
    lo, hi = 0, max_steps
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if spectral_radius(transition(mid)) < 1.0:
            lo = mid
        else:
            hi = mid
    return lo


# --- the study ------------------------------------------------------------------------------


def fmt_tau(tau):
    return 'inf' if math.isinf(tau) else '%.4f' % tau


def reference_rows(d, regimes, omegas):
    """Per omega and regime: the reference loop's and the fast-adaptation loop's margins."""
    rows = []
    for om in omegas:
        for _, _, th in regimes:
            rows.append(
                dict(
                    omega=om,
                    scale=float(th[0]),
                    stable=reference_closed_loop_stable(d, om, th),
                    ref=delay_margin(reference_loop(d, om, th)),
                    fast=delay_margin(fast_adaptation_loop(d, om, th)),
                )
            )
    return rows


def l1_margins(d, omega, gamma, regimes, x_eq, applied=False):
    """The linearised continuous l1's margin per regime at theta_hat* = theta (nan: unstable
    without delay)."""
    out = []
    for _, _, th in regimes:
        L, stable = l1_loop(d, omega, gamma, th, x_eq, th, applied)
        out.append(delay_margin(L, points=4000)[0] if stable else math.nan)
    return out


def discrete_reference_check(d, omega, theta, tau, max_steps):
    """The sampled reference system (dt, whole samples of delay) against the continuous margin
    tau: (stable at floor(tau/dt) - 1, unstable at ceil(tau/dt) + 1), or (stable at max_steps,
    None) when tau is infinite."""

    def stable(N):
        return spectral_radius(reference_discrete(d, omega, theta, N)) < 1.0

    if math.isinf(tau):
        return stable(max_steps), None
    return stable(math.floor(tau / d.dt) - 1), not stable(math.ceil(tau / d.dt) + 1)


def _cells(taus):
    return ' | '.join('unstable' if math.isnan(t) else fmt_tau(t) for t in taus)


def main(argv=None, description=__doc__):
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument('--omegas', default='10,20,50,150', help='filter bandwidths [rad/s]')
    ap.add_argument(
        '--gammas', default='1e2,1e3,1e4,1e5,1e6,1e7,1e8', help='Gamma of the linearised l1'
    )
    ap.add_argument(
        '--check-discrete',
        action='store_true',
        help='check the reference margins on the sampled loop (dt, whole samples; slow)',
    )
    ap.add_argument(
        '--at',
        metavar='SCALE:OMEGA:GAMMA:TH0,TH1,TH2',
        action='append',
        default=[],
        help='only the linearised l1 (dt -> 0) of regime theta = SCALE x ones at the estimate '
        'theta_hat* = TH (e.g. one a run ended on): its delay margin (repeatable)',
    )
    args = ap.parse_args(argv)
    d = load_design()
    regimes, r = scenario_regimes()
    if args.at:
        x_eq = l1_equilibrium(d, r)
        for spec in args.at:
            scale, om, g, th_hat = spec.split(':')
            th = float(scale) * np.ones(len(d.B))
            th_hat = np.array([float(v) for v in th_hat.split(',')])
            L, stable = l1_loop(d, float(om), float(g), th, x_eq, th_hat)
            tau = delay_margin(L, points=4000)[0] if stable else math.nan
            print(
                'theta %s x ones, omega %s, Gamma %s, theta_hat* %s: delay margin %s s'
                % (scale, om, g, th_hat.tolist(), 'unstable' if math.isnan(tau) else fmt_tau(tau))
            )
        return 0
    omegas = [float(w) for w in args.omegas.split(',')]
    gammas = [float(g) for g in args.gammas.split(',') if g]
    x_eq = l1_equilibrium(d, r)
    scales = ' | '.join('theta %g' % th[0] for _, _, th in regimes)
    rule = '|---' * (len(regimes) + 2) + '|'
    print('K = %s, K B = %.4f, x* = %s' % (np.round(d.K, 4).tolist(), d.K @ d.B, np.round(x_eq, 4)))
    rows = reference_rows(d, regimes, omegas)
    for key, name in (('ref', 'reference system'), ('fast', 'fast-adaptation loop')):
        print('\n%s: delay margin [s] (crossover [rad/s], PM [deg])' % name)
        print('| omega [rad/s] | %s | worst |' % scales)
        print(rule)
        for om in omegas:
            cells = []
            for row in (x for x in rows if x['omega'] == om):
                tau, wc, pm = row[key]
                c = fmt_tau(tau) + ('' if wc is None else ' (%.2f, %.1f)' % (wc, pm))
                cells.append(c if row['stable'] else c + ' closed loop unstable')
            worst = min(x[key][0] for x in rows if x['omega'] == om)
            print('| %g | %s | %s |' % (om, ' | '.join(cells), fmt_tau(worst)))
    for applied in (False, True):
        print(
            '\nl1 linearised at theta_hat* = theta, dt -> 0, predictor driven by the %s: delay '
            'margin [s]' % ('applied u_ad (delay known)' if applied else 'command (as built)')
        )
        print('| omega [rad/s] | Gamma | %s | worst |' % scales)
        print(rule + '---|')
        for om in omegas:
            for g in gammas:
                taus = l1_margins(d, om, g, regimes, x_eq, applied)
                worst = math.nan if any(map(math.isnan, taus)) else min(taus)
                print('| %g | %g | %s | %s |' % (om, g, _cells(taus), _cells([worst])))
    print(
        '\nsampled l1 (dt %g s, forward-Euler adaptation) at theta_hat* = theta, no delay: '
        'growth rate of its least stable mode [1/s] (> 0: unstable)' % d.dt
    )
    print('| omega [rad/s] | Gamma | %s |' % scales)
    print(rule)
    for om in omegas:
        for g in gammas:
            rates = [
                math.log(spectral_radius(l1_linearised(d, om, g, th, x_eq, th, 0))) / d.dt
                for _, _, th in regimes
            ]
            print('| %g | %g | %s |' % (om, g, ' | '.join('%.2f' % v for v in rates)))
    if args.check_discrete:
        print('\nsampled reference system (dt %g s, RK4 plant, the filter of l1_law.cpp):' % d.dt)
        for row in rows:
            th = row['scale'] * np.ones(len(d.B))
            lo, hi = discrete_reference_check(d, row['omega'], th, row['ref'][0], 2000)
            if hi is None:
                what = 'stable at 2000 samples: %s' % lo
            else:
                what = 'stable 1 sample below the margin: %s, unstable 1 above: %s' % (lo, hi)
            print('  omega %g theta %g: %s' % (row['omega'], row['scale'], what))
    return 0
